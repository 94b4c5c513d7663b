// The diagnosis: the calibrated model refit as the baseline, then every missing effect scored,
// refit, tested and ranked.
#include "trainer/diagnose/diagnose.hpp"

#include <algorithm>
#include <map>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <optional>
#include <utility>

#include "hostio/worker_threads.hpp"
#include "trainer/diagnose/in_words.hpp"
#include "trainer/diagnose/internal/block_test.hpp"
#include "trainer/diagnose/internal/refit.hpp"
#include "trainer/diagnose/internal/score_test.hpp"
#include "trainer/model/simulate.hpp"

namespace lptn::diagnose {
namespace {

constexpr double kNoTest = std::numeric_limits<double>::quiet_NaN();

// The refits' first steps on a grid this many times coarser than the data's: 1 s on 10 Hz data,
// TD3's scoring grid, which moves the error at LM's optimum by under 0.02 K (tests/lm, CoarseGrid);
// the polish on the data's own grid removes even that.
constexpr int kRefitCoarseFactor = 10;

lm::LmSettings lm_settings(const Settings& s) {
  lm::LmSettings lm;
  lm.threads = s.threads;
  lm.correlation_flag = s.correlation_flag;
  return lm;
}

// A refit's settings: at most Settings::refit_iterations (the candidates' and the coarse baseline's).
lm::LmSettings refit_settings(const Settings& s) {
  lm::LmSettings lm = lm_settings(s);
  lm.max_iterations = s.refit_iterations;
  return lm;
}

// LM's per-iteration report as a progress line of the stage it belongs to.
lm::LmProgress lm_progress(const Progress& progress, const std::string& stage) {
  if (!progress) return {};
  return [progress, stage](int iteration, double rmse, double) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s: iteration %d, rmse %.4f K", stage.c_str(), iteration, rmse);
    progress(buf);
  };
}

// The stator sensor's error over the cycles a split's metrics pooled: NaN without any.
double stator_rmse(const calibrate::SplitMetrics& m) { return m.cycles.empty() ? kNoTest : m.stator.rmse_k; }

// The held-out cycles' errors: the stator sensor's, and every measured sensor's (the RMS of the
// stator's and the rotor's residuals, each sample once; the stator alone would not see a
// recommendation that makes the rotor worse). NaN without test cycles.
struct HeldOut {
  double stator_k = kNoTest, combined_k = kNoTest;
};
HeldOut held_out(const calibrate::SplitMetrics& m) {
  if (m.cycles.empty()) return {};
  const double ns = static_cast<double>(m.stator.samples), nr = static_cast<double>(m.rotor.samples);
  HeldOut h;
  h.stator_k = m.stator.rmse_k;
  if (ns + nr > 0)
    h.combined_k = std::sqrt((ns * m.stator.rmse_k * m.stator.rmse_k + nr * m.rotor.rmse_k * m.rotor.rmse_k) / (ns + nr));
  return h;
}

// A parameter confounded with one the model has cannot be claimed whatever the fit gained (the
// correlation is the data's, present or absent the effect); one that is merely imprecise only
// matters once the gain is significant (an absent effect's parameter ends near zero, imprecise).
Verdict verdict(const Candidate& c, bool blocks_significant, const internal::Refit& refit, std::string& reason) {
  if (!refit.confounded.empty()) {
    reason = refit.confounded;
    return Verdict::not_distinguishable;
  }
  if (!(c.statistic > c.threshold)) return Verdict::not_significant;
  if (!blocks_significant) {
    char why[160];
    std::snprintf(why, sizeof why, "the gain is not consistent across the training cycles' blocks (t %.1f / %.1f over %d blocks)",
                  c.block_t, c.block_threshold, c.blocks);
    reason = why;
    return Verdict::not_significant;
  }
  if (!refit.imprecise.empty()) {
    reason = refit.imprecise;
    return Verdict::not_distinguishable;
  }
  return Verdict::significant;
}

struct Scored {
  int effect = -1;
  internal::Score score;
};

// The coarse grid the refits take their steps on, and the baseline refit there: a refit's
// likelihood ratio on the coarse grid is against it (the two grids' optima differ by more than
// a likelihood ratio's resolution: the baseline's fine-grid cost is not a coarse fit's footing).
struct CoarseGrid {
  calibrate::SharedDataset dataset;
  std::optional<lm::LmReport> baseline;  // none where the coarse grid keeps no reading
};

// A refit whose likelihood ratio on the coarse grid (against the baseline refit there) is below
// this share of its threshold is not polished: the polish moves a ratio by the grids' difference,
// not by half a threshold, and it is most of a refit's cost (on clean data a crawl along an absent
// effect's flat direction: windage's refit on a clean 6 h dump took 15 fine-grid iterations, 6.9 s
// of the diagnosis' 46). Its ratio and its figures are then the coarse fit's; its errors on the
// data's grid are evaluated with its parameters. Every candidate that can be significant is polished.
constexpr double kPolishShare = 0.5;

// The baseline's block errors by block length: refits whose residuals are short-correlated all get
// the shortest blocks, and share one simulation of the training cycles.
using BaselineBlocks = std::map<std::size_t, std::vector<double>>;

// The refit's second start: the effect's parameters where it does (next to) nothing, within the
// motor file's bounds (a term's heat at its 1 W floor), the rest at the baseline. From the score
// test's step alone a refit can end far above the baseline (a large term's local minimum); from
// here it starts at the baseline's parameters. Not at its cost: fit_lm starts each cycle's initial
// offsets afresh, and where the residual is slow (a missing thermal mass: correlation times of
// many minutes) a refit of refit_iterations can still end above the baseline. It then failed.
ParamVector<double> neutral_start(const model::MotorFile& with, int effect, const ParamVector<double>& baseline) {
  ParamVector<double> at = internal::neutral_point(baseline, effect);
  for (int i = 0; i < kNumParams; ++i)
    if (effect_of_param(i) == effect) {
      const model::ParameterSetting& p = with.parameters[static_cast<std::size_t>(i)];
      at[i] = std::clamp(at[i], p.min, p.max);
    }
  return at;
}

// Where the effect's neutral value lies beyond its first parameter's bound in the motor file (the
// sensor lag: neutral 0 s, its floor 0.5 s), the refit cannot switch it off: held at that bound it
// can end above the baseline from every start, which says the data pull the effect towards
// nothing past what the bound allows, not that the fit got lost. The bound it is held at, in
// words ("sensor_time_constant_s = 0.5 s"), or empty where it is not held there.
std::string held_at_neutral_bound(const model::MotorFile& with, int effect, const ParamVector<double>& values) {
  const int i = kNumPaperParams + EffectLibrary::kParamOffsets[static_cast<std::size_t>(effect)];
  const model::ParameterSetting& p = with.parameters[static_cast<std::size_t>(i)];
  const double neutral = param_spec(i).neutral, v = values[i];
  const double bound = neutral < p.min ? p.min : neutral > p.max ? p.max : std::numeric_limits<double>::quiet_NaN();
  if (std::isnan(bound) || std::abs(v - bound) > 1e-6 * std::max(1.0, std::abs(bound))) return {};
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s = %g %s", std::string(param_spec(i).name).c_str(), bound,
                std::string(param_spec(i).unit).c_str());
  return buf;
}

// A refit ending above the baseline by less than this, in likelihood-ratio units (a hundredth of
// any threshold), ended at the baseline: the tolerance of LM's convergence, not a worse fit.
constexpr double kAtBaselineLr = 0.1;

std::string kelvin_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f K", v);
  return buf;
}

// "from the score test's step to 2.417 K (converged, 2 iterations)": where one start ended.
std::string ended(const RefitStart& s) {
  if (!s.error.empty()) return "from " + s.from + " no fit (" + s.error + ")";
  char buf[200];
  std::snprintf(buf, sizeof buf, "from %s to %.3f K%s (%s, %d iterations)", s.from.c_str(), s.rmse_k,
                s.coarse_only ? " on the coarse grid, not polished" : "", s.converged ? "converged" : "not converged",
                s.iterations);
  return buf;
}

// The candidate judged at the baseline: the constrained fit is the baseline itself (the data pull
// the effect below its neutral value, or every refit ends back there), and its likelihood ratio 0.
void at_baseline(Candidate& c, const Diagnosis& before, const ParamVector<double>& effect_values, std::string reason) {
  c.refit = before.baseline;
  for (int i = 0; i < kNumParams; ++i)
    if (effect_of_param(i) == c.effect) c.refit.values[i] = effect_values[i];
  c.refit_rmse_k = before.rmse_k;
  c.statistic = 0;
  c.train_stator_rmse_k = before.train_stator_rmse_k;
  c.test_stator_rmse_k = before.test_stator_rmse_k;
  c.test_rmse_k_after = before.test_rmse_k;
  c.verdict = Verdict::not_significant;
  c.reason = std::move(reason);
}

Candidate examine(const model::MotorFile& motor, const Scored& scored, const Diagnosis& before, calibrate::DatasetRef dataset,
                  const CoarseGrid& coarse, const calibrate::Split& split, const Settings& settings, const Progress& progress,
                  BaselineBlocks& baseline_blocks) {
  const int effect = scored.effect;
  const auto e = static_cast<std::size_t>(effect);
  model::MotorFile with = motor;
  model::enable_effect(with, effect);
  Candidate c;
  c.effect = effect;
  c.name = EffectLibrary::kNames[e];
  c.kind = EffectLibrary::kKinds[e];
  c.node = node_id(effect);
  c.formula = EffectLibrary::kFormulas[e];
  c.df = EffectLibrary::kParamCounts[e];
  c.needs = EffectLibrary::kNeeds[e];
  const internal::Score& score = scored.score;
  c.score = score.statistic;
  // The score test's footing may be the coarse grid's baseline: the fall it predicts as a share
  // of that footing's error, applied to the baseline's error on the data's grid.
  c.predicted_rmse_k = score.rss_k2 > 0 ? before.rmse_k * std::sqrt(std::max(0.0, score.rss_k2 - score.reduction_k2) / score.rss_k2)
                                        : before.rmse_k;

  c.threshold = chi_square_quantile(1.0 - settings.level, c.df);
  if (!score.feasible) {
    // One-sided: the data would need the effect below its neutral value. The constrained fit is
    // the baseline itself, so there is nothing to refit.
    at_baseline(c, before, score.predicted, "the data pull it below its neutral value (no refit)");
    c.words = in_words(effect, score.predicted);
    return c;
  }

  // Two starts, the better kept: the score test's step (where the residuals point) and the
  // neutral value (the baseline's own fit). The neutral value is skipped where the step did not
  // move. Both run on the coarse grid, and the one that ends lower there is polished on the data's
  // own (the polish is most of a refit's cost); without readings on the coarse grid, both on the
  // data's. The neutral value runs first, and on the coarse grid the step's mark is the likelihood
  // ratio the neutral value reached where that is above the polish's: the step's refit matters only
  // where it ends lower, and one that cannot at twice its pace is ended there (on the clean 200 h
  // dump the neutral value ended lower for each of the three candidates polished, and each step's
  // refit crawled its 15 coarse iterations, 4 s a candidate, to end above it).
  const lm::LmSettings lm = refit_settings(settings);
  // The refit settings that stop a refit whose likelihood ratio against `base_cost` cannot reach `mark`.
  auto stopping_short_of = [&](double mark, double base_cost, int pace_iterations = internal::kPaceIterations) {
    lm::LmSettings stopping = lm;
    stopping.stop = internal::stop_short_of(mark, base_cost, before.effective_residuals, lm.max_iterations, kAtBaselineLr,
                                            pace_iterations);
    return stopping;
  };
  const std::pair<const char*, ParamVector<double>> starts[] = {
      {"the score test's step", score.predicted}, {"the neutral value", neutral_start(with, effect, before.baseline.values)}};
  std::optional<internal::Refit> kept;
  std::optional<lm::LmReport> best_coarse;
  std::size_t best_start = 0;  // in `starts` while they run, then in c.starts
  std::optional<RefitStart> tried[std::size(starts)];
  for (const std::size_t k : {std::size_t{1}, std::size_t{0}}) {
    const auto& [from, values] = starts[k];
    if (k == 1 && values == starts[0].second) continue;
    RefitStart s;
    s.from = from;
    const lm::LmProgress report = lm_progress(progress, c.name + ": refit from " + from);
    // On the coarse grid its mark is the polish (below it the verdict is the coarse fit's), or what
    // the start before it reached where higher; on the data's the threshold.
    const double coarse_mark =
        best_coarse ? std::max(kPolishShare * c.threshold,
                               before.effective_residuals * std::log(coarse.baseline->final_cost / best_coarse->final_cost))
                    : kPolishShare * c.threshold;
    try {
      if (std::optional<lm::LmReport> on_coarse =
              coarse.baseline
                  ? internal::coarse_stage(with, values, coarse.dataset, split.train,
                                           stopping_short_of(coarse_mark, coarse.baseline->final_cost), report)
                  : std::nullopt) {
        s.rmse_k = on_coarse->rmse_k;
        s.iterations = on_coarse->iterations;
        s.converged = on_coarse->converged;
        s.coarse_only = true;
        if (!best_coarse || on_coarse->final_cost < best_coarse->final_cost) {
          best_coarse = std::move(on_coarse);
          best_start = k;
        }
      } else {
        internal::Refit r = internal::refit_with(with, effect, values, dataset, split.train,
                                                 stopping_short_of(c.threshold, before.baseline.final_cost), report);
        s.rmse_k = r.fit.rmse_k;
        s.iterations = r.fit.iterations;
        s.converged = r.fit.converged;
        if (!kept || r.fit.final_cost < kept->fit.final_cost) {
          kept = std::move(r);
          c.start = from;
        }
      }
    } catch (const lm::ModelNotSimulable& error) {
      s.rmse_k = kNoTest;
      s.error = error.what();
    }
    tried[k] = s;
  }
  // In the starts' order: the step, then the neutral value.
  for (std::size_t k = 0; k < std::size(starts); ++k) {
    if (!tried[k]) continue;
    if (best_coarse && k == best_start) best_start = c.starts.size();
    c.starts.push_back(*tried[k]);
  }
  // The kept start's likelihood ratio on the coarse grid: where it is far below the threshold the
  // polish is skipped, and the ratio and the errors are the coarse fit's.
  double lr_coarse = std::numeric_limits<double>::quiet_NaN();
  if (best_coarse) {
    lr_coarse = before.effective_residuals * std::log(coarse.baseline->final_cost / best_coarse->final_cost);
    if (lr_coarse < kPolishShare * c.threshold) {
      kept = internal::judged(*best_coarse, with, effect);
      c.start = c.starts[best_start].from;
      best_coarse.reset();
    } else {
      lr_coarse = std::numeric_limits<double>::quiet_NaN();
    }
  }
  if (best_coarse) {
    RefitStart& s = c.starts[best_start];
    try {
      kept = internal::polish(with, effect,
                              internal::polish_start(with, *best_coarse, before.baseline, *coarse.baseline, dataset,
                                                     split.train, settings.threads),
                              dataset, split.train,
                              stopping_short_of(c.threshold, before.baseline.final_cost, internal::kPolishPaceIterations),
                              lm_progress(progress, c.name + ": polish from " + s.from));
      s.rmse_k = kept->fit.rmse_k;
      s.iterations = kept->fit.iterations;
      s.converged = kept->fit.converged;
      s.coarse_only = false;
      c.start = s.from;
    } catch (const lm::ModelNotSimulable& error) {
      s.rmse_k = kNoTest;
      s.error = error.what();
    }
  }
  // Both fits have the same residuals: the likelihood ratio of the kept refit against the baseline
  // (on the coarse grid where it was not polished).
  const bool unpolished = !std::isnan(lr_coarse);
  const double lr = unpolished ? lr_coarse
                    : kept     ? before.effective_residuals * std::log(before.baseline.final_cost / kept->fit.final_cost)
                               : -std::numeric_limits<double>::infinity();
  // The kept refit's training error on the data's grid: an unpolished one's is the baseline's
  // scaled by the two fits' ratio on the coarse grid (the likelihood ratio's footing).
  const double kept_rmse_k =
      unpolished ? before.rmse_k * std::sqrt(kept->fit.final_cost / coarse.baseline->final_cost) : kept ? kept->fit.rmse_k : kNoTest;
  if (lr < -kAtBaselineLr && kept) {
    if (const std::string bound = held_at_neutral_bound(with, effect, kept->fit.values); !bound.empty()) {
      // Held at the bound before its neutral value: the constrained fit's best is the baseline.
      at_baseline(c, before, kept->fit.values,
                  "the data pull it towards nothing, past the motor file's bound " + bound + " (its refit ends " +
                      "there, above the baseline's " +
                      (unpolished ? kelvin_text(coarse.baseline->rmse_k) + " on the coarse grid" : kelvin_text(before.rmse_k)) +
                      ")");
      c.words = in_words(effect, kept->fit.values);
      return c;
    }
  }
  if (lr < -kAtBaselineLr) {
    // Above the baseline from every start: the fit got lost (a local minimum, a crawl cut short),
    // and where it ended says nothing about the effect. Listed, not judged.
    std::string why;
    for (const RefitStart& s : c.starts) why += (why.empty() ? "" : "; ") + ended(s);
    c.verdict = Verdict::refit_failed;
    c.reason = "the refit ends above the baseline's " +
               (unpolished ? kelvin_text(coarse.baseline->rmse_k) + " on the coarse grid" : kelvin_text(before.rmse_k)) +
               " from every start (" + why + ")";
    c.refit = kept ? kept->fit : before.baseline;
    c.refit_rmse_k = kept_rmse_k;
    c.train_stator_rmse_k = c.test_stator_rmse_k = c.test_rmse_k_after = kNoTest;
    c.words = in_words(effect, score.predicted);
    return c;
  }
  if (lr <= 0) {
    // Back at the baseline within LM's tolerance: the data do not move the effect from nothing.
    std::string how;
    for (const RefitStart& s : c.starts)
      if (s.from == c.start) how = ended(s);
    at_baseline(c, before, kept->fit.values,
                "the refit ends back at the baseline's " +
                    (unpolished ? kelvin_text(coarse.baseline->rmse_k) + " on the coarse grid" : kelvin_text(before.rmse_k)) +
                    " (" + how +
                    "): the data do not move the effect from nothing");
    c.words = in_words(effect, kept->fit.values);
    return c;
  }
  const internal::Refit& refit = *kept;
  c.refit = refit.fit;
  c.refit_rmse_k = kept_rmse_k;
  c.words = in_words(effect, refit.fit.values);
  c.statistic = lr;
  const Model<double> model = with.model();
  // Blocks as long as the refit's residuals stay correlated: where the effect is absent the refit
  // leaves the misfit's slow structure (long blocks, few, a high quantile); where it explains the
  // structure, what is left is nearly white and the blocks can be short.
  // (An unpolished refit's correlation time is in the coarse grid's steps.)
  const double correlation_steps = refit.fit.correlation_time * (unpolished ? kRefitCoarseFactor : 1);
  const std::size_t block_steps = internal::block_steps(correlation_steps, dataset.cycles.front().dt_s);
  auto [baseline, fresh] = baseline_blocks.try_emplace(block_steps);
  if (fresh)
    baseline->second =
        internal::block_errors(motor.model(), before.baseline.values, dataset, split.train, block_steps, settings.threads);
  // The refit's one simulation of every cycle: its blocks, its training and held-out errors.
  const internal::SplitRun run = internal::run_split(model, refit.fit.values, dataset, split, block_steps, settings.threads);
  const internal::BlockTest blocks = internal::block_test(baseline->second, run.train_blocks, settings.block_level);
  c.blocks = blocks.blocks;
  c.block_gain = blocks.mean_gain;
  c.block_t = blocks.t;
  c.block_threshold = blocks.threshold;
  c.verdict = verdict(c, blocks.significant, refit, c.reason);
  c.train_stator_rmse_k = stator_rmse(run.train);
  const HeldOut after = held_out(run.test);
  c.test_stator_rmse_k = after.stator_k;
  c.test_rmse_k_after = after.combined_k;
  return c;
}

}  // namespace

const char* to_string(Verdict v) {
  switch (v) {
    case Verdict::significant: return "significant";
    case Verdict::not_distinguishable: return "not distinguishable";
    case Verdict::not_significant: return "not significant";
    case Verdict::refit_failed: return "refit failed";
  }
  return "?";
}

bool pinned(const Candidate& c, std::string* why) {
  if (c.effect < 0) return false;
  const int i = kNumPaperParams + EffectLibrary::kParamOffsets[static_cast<std::size_t>(c.effect)];
  const double v = c.refit.values[i], se = c.refit.std_error[i];
  if (std::isfinite(se) && se <= kPinnedRatio * std::abs(v)) return true;
  if (why) {
    char buf[256];
    if (std::isfinite(se))
      std::snprintf(buf, sizeof buf, "its size is not pinned: %s = %.3g +- %.2g %s, a standard error of %.0f %% of the "
                    "value (at most %.0f %%)", std::string(param_spec(i).name).c_str(), v, se,
                    std::string(param_spec(i).unit).c_str(), 100 * se / std::abs(v), 100 * kPinnedRatio);
    else
      std::snprintf(buf, sizeof buf, "its size is not pinned: %s = %.3g has no standard error",
                    std::string(param_spec(i).name).c_str(), v);
    *why = buf;
  }
  return false;
}

bool Diagnosis::raises_held_out_error(const Candidate& c) const {
  return !std::isnan(test_rmse_k) && !std::isnan(c.test_rmse_k_after) && c.test_rmse_k_after > test_rmse_k;
}

const SensorFinding* Diagnosis::sensor_fault() const {
  const SensorFinding* best = nullptr;
  for (const SensorFinding& s : sensors)
    if (s.found && (best == nullptr || s.p_value < best->p_value)) best = &s;
  return best;
}

std::string Diagnosis::not_recommended_because(const Candidate& c) const {
  if (const SensorFinding* s = sensor_fault())
    return "a sensor reads wrong (" + s->finding + "): an effect would absorb the fault";
  if (drift.found) return "the dump drifts between cycles (" + drift.finding + "): an effect would absorb the change";
  std::string why;
  if (!pinned(c, &why)) return why;
  if (!std::isnan(test_rmse_k) && !std::isnan(c.test_rmse_k_after) && !(c.test_rmse_k_after < test_rmse_k)) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "it does not lower the held-out error (%.3f -> %.3f K, every sensor): it learned the "
                  "training cycles, not the physics", test_rmse_k, c.test_rmse_k_after);
    return buf;
  }
  return {};
}

const Candidate* Diagnosis::best() const {
  for (const Candidate& c : candidates)
    if (c.verdict == Verdict::significant && not_recommended_because(c).empty()) return &c;
  return nullptr;
}

Diagnosis diagnose(const model::MotorFile& motor, const ParamVector<double>& calibrated, calibrate::DatasetRef dataset,
                   const calibrate::Split& split, const Settings& settings, const Progress& progress) {
  Diagnosis d;
  // Refit from the calibration (a few iterations at most): it gives the per-cycle initial
  // offsets and the residuals' correlation time, and an RSS on exactly the footing of the refits.
  d.baseline = lm::fit_lm(motor, calibrated, dataset, split.train, lm_settings(settings),
                      lm_progress(progress, "the model as calibrated"));
  d.rmse_k = d.baseline.rmse_k;
  d.effective_residuals = static_cast<double>(d.baseline.residuals) / d.baseline.correlation_time;
  const Model<double> model = motor.model();
  // One simulation of every cycle at the baseline: the adequacy and the "before" figures.
  d.adequacy = assess_adequacy(model, d.baseline.values, dataset, split, settings.threads);
  d.train_stator_rmse_k = stator_rmse(d.adequacy.train);
  const HeldOut before = held_out(d.adequacy.test);
  d.test_stator_rmse_k = before.stator_k;
  d.test_rmse_k = before.combined_k;
  if (progress) progress("drift between cycles");
  {
    // The adequacy's simulations are the drift's at factor 1: the same metrics, not simulated again.
    std::vector<const calibrate::CycleMetrics*> simulated(dataset.cycles.size(), nullptr);
    for (std::size_t i = 0; i < split.train.size() && i < d.adequacy.train.cycles.size(); ++i)
      simulated[split.train[i]] = &d.adequacy.train.cycles[i];
    for (std::size_t i = 0; i < split.test.size() && i < d.adequacy.test.cycles.size(); ++i)
      simulated[split.test[i]] = &d.adequacy.test.cycles[i];
    d.drift = find_drift(model, d.baseline.values, dataset.data, settings.threads, simulated);
  }
  if (progress) progress("sensor faults");
  d.sensors = check_sensors(model, d.baseline.values, dataset.data, settings.threads);
  if (const SensorFinding* s = d.sensor_fault(); s && d.drift.found) {
    // The sensor check weighed the heat balance cycle by cycle and found the sensor's shift explains
    // the faulty cycles better: the drift the per-cycle factors show is the sensor's.
    d.drift.found = false;
    d.drift.finding = "not the motor's: the " + std::string(data::sensor_name(s->sensor)) +
                      " sensor's fault explains the change between cycles better (" + d.drift.finding + ")";
  }

  std::vector<Scored> terms;
  BaselineBlocks baseline_blocks;
  // Each refit takes its steps on the 1 s grid and polishes on the data's (refit.hpp).
  CoarseGrid coarse{internal::coarse_dataset(dataset, kRefitCoarseFactor), std::nullopt};
  internal::correct_for_grid(coarse.dataset, dataset, model, d.baseline.values, split.train, d.baseline.offsets,
                             settings.threads);
  // The fits on the 1 s grid (the baseline's there, every score test and refit: dozens of
  // simulations of each training cycle) share its inputs as the model prepares them: their pow()
  // calls were a tenth of a 200 h diagnosis. 152 bytes a step of the 1 s grid: 73 MB for the 133 h
  // of a 200 h dump's training cycles. Every refit's model is this motor's (effects do not enter).
  coarse.dataset.prepared.resize(coarse.dataset.data.cycles.size());
  const calibrate::DatasetRef on_coarse(coarse.dataset);
  hostio::parallel_for(split.train.size(), settings.threads, [&](std::size_t i) {
    const std::size_t c = split.train[i];
    if (!on_coarse.remote(c)) coarse.dataset.prepared[c] = lptn::model::prepare_cycle(model, on_coarse.cycles[c]);
  });
  {
    lm::LmSettings lm = refit_settings(settings);
    lm.start_offsets = d.baseline.offsets;
    coarse.baseline =
        internal::coarse_stage(motor, d.baseline.values, coarse.dataset, split.train, lm,
                               lm_progress(progress, "the model as calibrated, on the coarse grid"));
  }
  std::vector<int> missing;
  for (int e = 0; e < kNumEffects; ++e)
    if (!(motor.effects & effect_bit(e))) missing.push_back(e);
  // The score tests on the coarse grid, at the baseline refit there: a score asks which way the
  // residuals point, a question of minutes that the 1 s grid answers at a tenth of the cost (the
  // joint Jacobian of every term on the data's grid was half of a diagnosis). The refits start
  // from their steps on that grid and are judged by their likelihood ratios, polished where that
  // can matter. An effect scored off its neutral value (the sensor lag: its score is the limit's
  // sensitivity, -dT1/dt, which 1 s averages blunt) is scored on the data's grid.
  const auto on_data_grid = [&](int e) {
    return !coarse.baseline || !std::isnan(EffectLibrary::kScoreAt[static_cast<std::size_t>(e)]);
  };
  std::vector<int> coarse_missing, fine_missing;
  for (int e : missing) (on_data_grid(e) ? fine_missing : coarse_missing).push_back(e);
  const auto scoring = [&](int e) {
    if (progress)
      progress(e < 0 ? std::string("score tests") : std::string(EffectLibrary::kNames[static_cast<std::size_t>(e)]) + ": score test");
  };
  const std::vector<internal::Score> fine_scores =
      internal::score_tests(motor, fine_missing, d.baseline, dataset, split.train, settings.threads, scoring);
  const std::vector<internal::Score> coarse_scores =
      coarse_missing.empty() ? std::vector<internal::Score>{}
                             : internal::score_tests(motor, coarse_missing, *coarse.baseline, coarse.dataset,
                                                     split.train, settings.threads, scoring);
  // A score counts its residuals' independent samples as its grid does; the coarse ones are put
  // on the data grid's count (the likelihood ratios' footing): the 1 s grid's readings, a tenth,
  // are each less correlated with their neighbours, and on a clean 48 h dump its count came to
  // about 1.6 times the data grid's, and so did every term's score.
  const double on_data_count =
      coarse.baseline ? d.effective_residuals / (static_cast<double>(coarse.baseline->residuals) / coarse.baseline->correlation_time)
                      : 1.0;
  std::vector<internal::Score> scores;
  for (std::size_t k = 0, f = 0, c = 0; k < missing.size(); ++k) {
    if (on_data_grid(missing[k])) {
      scores.push_back(fine_scores[f++]);
      continue;
    }
    scores.push_back(coarse_scores[c++]);
    scores.back().statistic *= on_data_count;
  }
  for (std::size_t k = 0; k < missing.size(); ++k) {
    const Scored scored{missing[k], scores[k]};
    if (EffectLibrary::kKinds[static_cast<std::size_t>(scored.effect)] == EffectKind::library)
      d.candidates.push_back(examine(motor, scored, d, dataset, coarse, split, settings, progress, baseline_blocks));
    else
      terms.push_back(scored);
  }
  // The dictionary: every term scored, the best few refit and tested like library effects.
  std::stable_sort(terms.begin(), terms.end(), [](const Scored& a, const Scored& b) {
    return (a.score.feasible ? a.score.statistic : -1.0) > (b.score.feasible ? b.score.statistic : -1.0);
  });
  for (const Scored& t : terms)
    d.term_scores.push_back({t.effect, std::string(EffectLibrary::kNames[static_cast<std::size_t>(t.effect)]),
                             t.score.statistic, t.score.feasible});
  // The best-scoring form of each node's heat, and each other term: the forms of one node's heat
  // (I^2 f^k, psi^2 f^k, speed^k, power^k) point nearly the same way at their neutral value and
  // score alike (a missing thermal mass behind the stator core: four stator-core heat forms at 29..32
  // between the winding's mass at 33 and the core's at 28, in the score tests of before they were
  // exact), so a second form of it would spend a refit on what the first already asked.
  std::vector<std::string_view> groups;
  int refits = 0;
  for (const Scored& t : terms) {
    if (refits >= settings.term_refits) break;
    const auto e = static_cast<std::size_t>(t.effect);
    if (!t.score.feasible || EffectLibrary::kRefinesGroup[e]) continue;
    const std::string_view group = EffectLibrary::kRefitGroups[e];
    if (std::find(groups.begin(), groups.end(), group) != groups.end()) continue;
    groups.push_back(group);
    ++refits;
    d.candidates.push_back(examine(motor, t, d, dataset, coarse, split, settings, progress, baseline_blocks));
  }
  // A refinement of a group (a step: heat that switches on) points like its group at the score
  // test and only a refit tells it apart: the best-scoring one is refit beside a group's refit that
  // is significant, outside the budget. On clean data no group is, and nothing more is refit.
  const std::size_t examined = d.candidates.size();
  for (std::size_t i = 0; i < examined; ++i) {
    const Candidate& found = d.candidates[i];
    if (found.kind != EffectKind::term || found.verdict != Verdict::significant) continue;
    const std::string_view group = EffectLibrary::kRefitGroups[static_cast<std::size_t>(found.effect)];
    for (const Scored& t : terms) {
      const auto e = static_cast<std::size_t>(t.effect);
      if (!t.score.feasible || !EffectLibrary::kRefinesGroup[e] || EffectLibrary::kRefitGroups[e] != group) continue;
      d.candidates.push_back(examine(motor, t, d, dataset, coarse, split, settings, progress, baseline_blocks));
      break;
    }
  }
  // The library first: a named effect with its physics and reference is preferred to a generic
  // term that fits as well or a little better (a term with a free exponent contains windage's
  // square law); the dictionary speaks where the library has nothing to say, and where a term
  // explains significantly more than the library's best: its likelihood ratio above that one's by
  // more than the term's own threshold (the two fits' likelihood ratio, both against one baseline).
  // Recirculating exhaust air: windage 14.5, the cooling air's exponent on both sides 41.1 over a
  // threshold of 10.8, and only the second brings the held-out error to the noise. Each group by
  // refit; failed refits last: they were not judged.
  double best_library_lr = -std::numeric_limits<double>::infinity();
  for (const Candidate& c : d.candidates)
    if (c.kind == EffectKind::library && c.verdict == Verdict::significant) best_library_lr = std::max(best_library_lr, c.statistic);
  const auto rank = [&](const Candidate& c) {
    if (c.verdict == Verdict::refit_failed) return 3;
    if (c.kind == EffectKind::library) return 1;
    const bool outdoes_library = std::isfinite(best_library_lr) && c.statistic - best_library_lr > c.threshold;
    return c.verdict == Verdict::significant && outdoes_library ? 0 : 2;
  };
  std::stable_sort(d.candidates.begin(), d.candidates.end(), [&](const Candidate& a, const Candidate& b) {
    if (rank(a) != rank(b)) return rank(a) < rank(b);
    return a.refit_rmse_k < b.refit_rmse_k;
  });
  return d;
}

Selection select_effects(const model::MotorFile& motor, const ParamVector<double>& calibrated, calibrate::DatasetRef dataset,
                         const calibrate::Split& split, const Settings& settings, const Progress& progress,
                         const RoundDone& round_done) {
  Selection s;
  s.motor = motor;
  ParamVector<double> values = calibrated;
  // Each round adds an effect or ends, so there are at most kNumEffects + 1 rounds.
  for (;;) {
    s.rounds.push_back(diagnose(s.motor, values, dataset, split, settings, progress));
    const Diagnosis& d = s.rounds.back();
    if (round_done) round_done(d);
    const Candidate* best = d.best();
    if (best == nullptr) break;
    model::enable_effect(s.motor, best->effect);
    values = best->refit.values;
    s.added.push_back(best->name);
  }
  return s;
}

}  // namespace lptn::diagnose
