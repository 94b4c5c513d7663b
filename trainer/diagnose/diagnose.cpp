// The diagnosis: the calibrated model refit as the baseline, then every missing effect scored,
// refit, tested and ranked.
#include "trainer/diagnose/diagnose.hpp"

#include <algorithm>
#include <map>
#include <cmath>
#include <cstdio>
#include <limits>

#include "trainer/diagnose/in_words.hpp"
#include "trainer/diagnose/internal/block_test.hpp"
#include "trainer/diagnose/internal/effect_notes.hpp"
#include "trainer/diagnose/internal/refit.hpp"
#include "trainer/diagnose/internal/score_test.hpp"

namespace lptn::diagnose {
namespace {

constexpr double kNoTest = std::numeric_limits<double>::quiet_NaN();

LmSettings lm_settings(const Settings& s) {
  LmSettings lm;
  lm.threads = s.threads;
  lm.correlation_flag = s.correlation_flag;
  return lm;
}

// LM's per-iteration report as a progress line of the stage it belongs to.
LmProgress lm_progress(const Progress& progress, const std::string& stage) {
  if (!progress) return {};
  return [progress, stage](int iteration, double rmse, double) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s: iteration %d, rmse %.4f K", stage.c_str(), iteration, rmse);
    progress(buf);
  };
}

double stator_rmse(const Model<double>& model, const ParamVector<double>& values, const data::Dataset& dataset,
                   const std::vector<std::size_t>& cycles, int threads) {
  if (cycles.empty()) return kNoTest;
  return evaluate_split(model, values, dataset, cycles, threads).stator.rmse_k;
}

// The held-out cycles' errors from one simulation of each: the stator sensor's, and every measured
// sensor's (the RMS of the stator's and the rotor's residuals, each sample once; the stator alone
// would not see a recommendation that makes the rotor worse). NaN without test cycles.
struct HeldOut {
  double stator_k = kNoTest, combined_k = kNoTest;
};
HeldOut held_out(const Model<double>& model, const ParamVector<double>& values, const data::Dataset& dataset,
                 const std::vector<std::size_t>& test, int threads) {
  if (test.empty()) return {};
  const SplitMetrics m = evaluate_split(model, values, dataset, test, threads);
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

Scored score_effect(const MotorFile& motor, int effect, const Diagnosis& before, const data::Dataset& dataset,
                    const Split& split, const Settings& settings, const Progress& progress) {
  MotorFile with = motor;
  enable_effect(with, effect);
  if (progress) progress(std::string(EffectLibrary::kNames[static_cast<std::size_t>(effect)]) + ": score test");
  return {effect, internal::score_test(with, effect, before.baseline, dataset, split.train, settings.threads)};
}

// The baseline's block errors by block length: refits whose residuals are short-correlated all get
// the shortest blocks, and share one simulation of the training cycles.
using BaselineBlocks = std::map<std::size_t, std::vector<double>>;

Candidate examine(const MotorFile& motor, const Scored& scored, const Diagnosis& before, const data::Dataset& dataset,
                  const Split& split, const Settings& settings, const Progress& progress, BaselineBlocks& baseline_blocks) {
  const int effect = scored.effect;
  const auto e = static_cast<std::size_t>(effect);
  MotorFile with = motor;
  enable_effect(with, effect);
  Candidate c;
  c.effect = effect;
  c.name = EffectLibrary::kNames[e];
  c.kind = EffectLibrary::kKinds[e];
  c.node = node_id(effect);
  c.formula = EffectLibrary::kFormulas[e];
  c.df = EffectLibrary::kParamCounts[e];
  c.needs = internal::notes_for(effect).needs;
  const internal::Score& score = scored.score;
  c.score = score.statistic;
  c.predicted_rmse_k = std::sqrt(std::max(0.0, score.rss_k2 - score.reduction_k2) / static_cast<double>(score.residuals));

  c.threshold = chi_square_quantile(1.0 - settings.level, c.df);
  if (!score.feasible) {
    // One-sided: the data would need the effect below its neutral value. The constrained fit is
    // the baseline itself, so there is nothing to refit.
    c.refit = before.baseline;
    c.refit_rmse_k = before.rmse_k;
    c.train_stator_rmse_k = before.train_stator_rmse_k;
    c.test_stator_rmse_k = before.test_stator_rmse_k;
    c.test_rmse_k_after = before.test_rmse_k;
    c.reason = "the data pull it below its neutral value (no refit)";
    c.words = in_words(effect, score.predicted);
    return c;
  }

  LmSettings lm = lm_settings(settings);
  lm.max_iterations = settings.refit_iterations;
  const internal::Refit refit =
      internal::refit_with(with, effect, score.predicted, dataset, split.train, lm, lm_progress(progress, c.name + ": refit"));
  c.refit = refit.fit;
  c.refit_rmse_k = refit.fit.rmse_k;
  c.words = in_words(effect, refit.fit.values);
  // Both fits have the same residuals; a refit that ends worse (a local minimum) gains nothing.
  c.statistic = std::max(0.0, before.effective_residuals * std::log(before.baseline.final_cost / refit.fit.final_cost));
  const Model<double> model = with.model();
  // Blocks as long as the refit's residuals stay correlated: where the effect is absent the refit
  // leaves the misfit's slow structure (long blocks, few, a high quantile); where it explains the
  // structure, what is left is nearly white and the blocks can be short.
  const std::size_t block_steps = internal::block_steps(refit.fit.correlation_time, dataset.cycles.front().dt_s);
  auto [baseline, fresh] = baseline_blocks.try_emplace(block_steps);
  if (fresh)
    baseline->second =
        internal::block_errors(motor.model(), before.baseline.values, dataset, split.train, block_steps, settings.threads);
  const internal::BlockTest blocks = internal::block_test(
      baseline->second, internal::block_errors(model, refit.fit.values, dataset, split.train, block_steps, settings.threads),
      settings.block_level);
  c.blocks = blocks.blocks;
  c.block_gain = blocks.mean_gain;
  c.block_t = blocks.t;
  c.block_threshold = blocks.threshold;
  c.verdict = verdict(c, blocks.significant, refit, c.reason);
  c.train_stator_rmse_k = stator_rmse(model, refit.fit.values, dataset, split.train, settings.threads);
  const HeldOut after = held_out(model, refit.fit.values, dataset, split.test, settings.threads);
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
  }
  return "?";
}

bool Diagnosis::raises_held_out_error(const Candidate& c) const {
  return !std::isnan(test_rmse_k) && !std::isnan(c.test_rmse_k_after) && c.test_rmse_k_after > test_rmse_k;
}

const Candidate* Diagnosis::best() const {
  if (drift.found) return nullptr;
  for (const Candidate& c : candidates)
    if (c.verdict == Verdict::significant && !raises_held_out_error(c)) return &c;
  return nullptr;
}

Diagnosis diagnose(const MotorFile& motor, const ParamVector<double>& calibrated, const data::Dataset& dataset,
                   const Split& split, const Settings& settings, const Progress& progress) {
  Diagnosis d;
  // Refit from the calibration (a few iterations at most): it gives the per-cycle initial
  // offsets and the residuals' correlation time, and an RSS on exactly the footing of the refits.
  d.baseline = fit_lm(motor, calibrated, dataset, split.train, lm_settings(settings),
                      lm_progress(progress, "the model as calibrated"));
  d.rmse_k = d.baseline.rmse_k;
  d.effective_residuals = static_cast<double>(d.baseline.residuals) / d.baseline.correlation_time;
  const Model<double> model = motor.model();
  d.train_stator_rmse_k = stator_rmse(model, d.baseline.values, dataset, split.train, settings.threads);
  const HeldOut before = held_out(model, d.baseline.values, dataset, split.test, settings.threads);
  d.test_stator_rmse_k = before.stator_k;
  d.test_rmse_k = before.combined_k;
  d.adequacy = assess_adequacy(model, d.baseline.values, dataset, split, settings.threads);
  if (progress) progress("drift between cycles");
  d.drift = find_drift(model, d.baseline.values, dataset, settings.threads);

  std::vector<Scored> terms;
  BaselineBlocks baseline_blocks;
  for (int e = 0; e < kNumEffects; ++e) {
    if (motor.effects & effect_bit(e)) continue;
    const Scored scored = score_effect(motor, e, d, dataset, split, settings, progress);
    if (EffectLibrary::kKinds[static_cast<std::size_t>(e)] == EffectKind::library)
      d.candidates.push_back(examine(motor, scored, d, dataset, split, settings, progress, baseline_blocks));
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
  for (std::size_t i = 0; i < terms.size() && static_cast<int>(i) < settings.term_refits; ++i)
    if (terms[i].score.feasible) d.candidates.push_back(examine(motor, terms[i], d, dataset, split, settings, progress, baseline_blocks));
  // The library first: a named effect with its physics and reference is preferred to a generic
  // term that fits as well or a little better (a term with a free exponent contains windage's
  // square law); the dictionary speaks where the library has nothing to say. Each group by refit.
  std::stable_sort(d.candidates.begin(), d.candidates.end(), [](const Candidate& a, const Candidate& b) {
    if (a.kind != b.kind) return a.kind == EffectKind::library;
    return a.refit_rmse_k < b.refit_rmse_k;
  });
  return d;
}

Selection select_effects(const MotorFile& motor, const ParamVector<double>& calibrated, const data::Dataset& dataset,
                         const Split& split, const Settings& settings, const Progress& progress,
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
    enable_effect(s.motor, best->effect);
    values = best->refit.values;
    s.added.push_back(best->name);
  }
  return s;
}

}  // namespace lptn::diagnose
