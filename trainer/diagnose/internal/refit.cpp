#include "trainer/diagnose/internal/refit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "hostio/worker_threads.hpp"
#include "trainer/calibrate/grid_residuals.hpp"
#include "trainer/data/coarse_grid.hpp"

#include "trainer/diagnose/internal/heat_path.hpp"
#include "trainer/diagnose/internal/sensor_traces.hpp"

namespace lptn::diagnose::internal {
namespace {

// "P is +0.97 correlated with Q" for the first flagged pair of parameter `i` with one the model
// already has, or empty. Two parameters of the effect itself (a term's size and its exponent)
// trading off against each other make its form imprecise, not the effect indistinguishable; a
// parameter with no heat path to the effect (a rotor conductance for a stator term, the sides
// unlinked) cannot stand in for it, whatever the fit's ill-conditioning makes of the pair.
std::string confounded(const lm::LmReport& fit, int i, int effect, EffectSet effects) {
  const std::string name(param_spec(i).name);
  for (const calibrate::CorrelatedPair& c : fit.correlated) {
    if (c.a != name && c.b != name) continue;
    const int other = param_index(c.a == name ? c.b : c.a);
    if (effect_of_param(other) == effect) continue;
    if (!shares_heat_path(other, effect, effects)) continue;
    char buf[256];
    std::snprintf(buf, sizeof buf, "%s is %+.3f correlated with %s", name.c_str(), c.correlation,
                  (c.a == name ? c.b : c.a).c_str());
    return buf;
  }
  return {};
}

// "P = v +- se: its standard error exceeds its value", or empty.
std::string imprecise(const lm::LmReport& fit, int i) {
  const std::string name(param_spec(i).name);
  const double v = fit.values[i], se = fit.std_error[i];
  if (std::isnan(se)) return name + " has no standard error (the data's information about it is singular)";
  if (se <= std::abs(v)) return {};
  char buf[256];
  std::snprintf(buf, sizeof buf, "%s = %.3g +- %.3g %s: its standard error exceeds its value", name.c_str(), v, se,
                std::string(param_spec(i).unit).c_str());
  return buf;
}

}  // namespace

calibrate::SharedDataset coarse_dataset(calibrate::DatasetRef fine, int factor) {
  calibrate::SharedDataset out;
  out.data.cycles.reserve(fine.cycles.size());
  for (std::size_t i = 0; i < fine.cycles.size(); ++i) {
    // diagnose's shared dataset keeps every cycle's samples on every rank (share_work): each
    // rank can make the coarse cycle, and count a remote one's residuals itself.
    out.data.cycles.push_back(data::coarse_grid(fine.cycles[i], factor));
    if (!fine.shared()) continue;
    calibrate::CycleShare share;
    share.remote = fine.remote(i);
    share.residuals = calibrate::count_grid_residuals(out.data.cycles.back());
    out.shares.push_back(std::move(share));
  }
  return out;
}

void correct_for_grid(calibrate::SharedDataset& coarse, calibrate::DatasetRef fine, const Model<double>& model,
                      const ParamVector<double>& at, const std::vector<std::size_t>& train,
                      const std::vector<model::InitialOffsets<double>>& offsets, int threads) {
  // diagnose's shared dataset keeps every cycle's samples on every rank: each corrects them all.
  hostio::parallel_for(train.size(), threads, [&](std::size_t i) {
    const data::Cycle& f = fine.cycles[train[i]];
    data::Cycle& c = coarse.data.cycles[train[i]];
    if (c.steps == 0 || f.steps == 0) return;
    const std::size_t factor = static_cast<std::size_t>(std::lround(c.dt_s / f.dt_s));
    const model::CycleSimulation on_fine = model::simulate_cycle(model, at, f, offsets[i]);
    const model::CycleSimulation on_coarse = model::simulate_cycle(model, at, c, offsets[i]);
    for (const SensorTrace& s : kSensorTraces) {
      if (!c.has(s.channel)) continue;
      std::vector<float>& readings = c.samples[data::index_of(s.channel)];
      const std::vector<float>& model_fine = on_fine.*s.trace;
      const std::vector<float>& model_coarse = on_coarse.*s.trace;
      for (std::size_t k = 0; k < c.steps && k < model_coarse.size() && k * factor < model_fine.size(); ++k)
        readings[k] = static_cast<float>(double(readings[k]) + (double(model_coarse[k]) - double(model_fine[k * factor])));
    }
  });
}

std::optional<lm::LmReport> coarse_stage(const model::MotorFile& with_effect, const ParamVector<double>& start,
                                     calibrate::DatasetRef coarse, const std::vector<std::size_t>& train,
                                     const lm::LmSettings& settings, const lm::LmProgress& progress) {
  // The counts include remote cycles', so every process decides alike.
  std::size_t coarse_readings = 0;
  for (std::size_t c : train) coarse_readings += coarse.residuals(c);
  if (coarse_readings == 0) return std::nullopt;
  return lm::fit_lm(with_effect, start, coarse, train, settings, progress);
}

std::function<bool(int, double)> stop_short_of(double mark, double base_cost, double effective_residuals,
                                               int max_iterations, double at_baseline, int pace_iterations) {
  std::vector<double> ratios;  // after each iteration
  return [=](int iteration, double cost) mutable {
    ratios.push_back(effective_residuals * std::log(base_cost / cost));
    if (iteration < pace_iterations || ratios.size() <= static_cast<std::size_t>(pace_iterations)) return false;
    const std::size_t n = ratios.size();
    double pace = 0;
    for (std::size_t k = n - static_cast<std::size_t>(pace_iterations); k < n; ++k) pace = std::max(pace, ratios[k] - ratios[k - 1]);
    const double now = ratios.back(), reach = now + kPaceMargin * pace * (max_iterations - iteration);
    // Above the baseline, only where it would end above it too.
    const bool ends_on_its_side = now >= -at_baseline || reach < -at_baseline;
    const bool stalled = iteration < max_iterations && reach - now < kStalledGain;
    return (stalled || reach < mark) && ends_on_its_side;
  };
}

Refit judged(lm::LmReport fit, const model::MotorFile& with_effect, int effect) {
  Refit out;
  out.fit = std::move(fit);
  // Whether the effect is there at all is its first parameter's question (a term's size; its
  // exponent may well be near zero and imprecise while the term is plainly present).
  const int first = kNumPaperParams + EffectLibrary::kParamOffsets[static_cast<std::size_t>(effect)];
  for (int i : calibrate::FreeParameters::from_motor(with_effect).index) {
    if (effect_of_param(i) != effect) continue;
    if (out.confounded.empty()) out.confounded = confounded(out.fit, i, effect, with_effect.effects);
    if (out.imprecise.empty() && i == first) out.imprecise = imprecise(out.fit, i);
  }
  return out;
}

lm::LmReport moved_to_fine(const model::MotorFile& with_effect, const lm::LmReport& on_coarse, const lm::LmReport& fine_baseline,
                       const lm::LmReport& coarse_baseline) {
  lm::LmReport out = on_coarse;
  const calibrate::FreeParameters free = calibrate::FreeParameters::from_motor(with_effect);
  for (std::size_t j = 0; j < free.size(); ++j) {
    const int i = free.index[j];
    // The effect's own parameters are fixed in both baselines (at equal values): they stay.
    if (fine_baseline.values[i] == coarse_baseline.values[i]) continue;
    const double shift = free.to_internal(j, fine_baseline.values[i]) - free.to_internal(j, coarse_baseline.values[i]);
    const double moved = free.to_internal(j, on_coarse.values[i]) + shift;
    out.values[i] = std::clamp(free.to_physical(j, moved), free.min[j], free.max[j]);
  }
  for (std::size_t k = 0; k < out.offsets.size() && k < fine_baseline.offsets.size() && k < coarse_baseline.offsets.size(); ++k) {
    out.offsets[k].stator_core += fine_baseline.offsets[k].stator_core - coarse_baseline.offsets[k].stator_core;
    out.offsets[k].rotor_core += fine_baseline.offsets[k].rotor_core - coarse_baseline.offsets[k].rotor_core;
  }
  return out;
}

namespace {

// Half the sum of squared residuals of `dataset`'s training cycles on its grid at `fit`'s values and
// initial offsets (infinite where the model does not stay finite). Every process sums every cycle
// (diagnose's shared dataset keeps each cycle's samples on each rank), so all decide alike.
double cost_on(const model::MotorFile& motor, const lm::LmReport& fit, calibrate::DatasetRef dataset, const std::vector<std::size_t>& train,
               int threads) {
  const Model<double> model = motor.model();
  std::vector<double> per_cycle(train.size(), 0.0);
  hostio::parallel_for(train.size(), threads, [&](std::size_t i) {
    double sum = 0;
    const bool finite = calibrate::for_each_grid_residual(model, fit.values, dataset.cycles[train[i]], fit.offsets[i],
                                               [&](double r) { sum += r * r; });
    per_cycle[i] = finite ? 0.5 * sum : std::numeric_limits<double>::infinity();
  });
  double cost = 0;
  for (double c : per_cycle) cost += c;
  return cost;
}

}  // namespace

lm::LmReport polish_start(const model::MotorFile& with_effect, const lm::LmReport& on_coarse, const lm::LmReport& fine_baseline,
                      const lm::LmReport& coarse_baseline, calibrate::DatasetRef dataset, const std::vector<std::size_t>& train,
                      int threads) {
  lm::LmReport moved = moved_to_fine(with_effect, on_coarse, fine_baseline, coarse_baseline);
  if (on_coarse.offsets.size() != train.size()) return moved;
  return cost_on(with_effect, moved, dataset, train, threads) <= cost_on(with_effect, on_coarse, dataset, train, threads)
             ? moved
             : on_coarse;
}

Refit polish(const model::MotorFile& with_effect, int effect, const lm::LmReport& on_coarse, calibrate::DatasetRef dataset,
             const std::vector<std::size_t>& train, const lm::LmSettings& settings, const lm::LmProgress& progress) {
  lm::LmSettings fine = settings;
  fine.start_offsets = on_coarse.offsets;
  // A coarse fit that used up its iterations is crawling along a direction the data barely
  // supports, and where it got is its verdict's ground (Settings::refit_iterations): the polish
  // then only takes the grid's bias out, at ten times the cost of a coarse step, instead of
  // crawling on (a thermal mass's refit on clean data: 15 fine-grid iterations, most of its time).
  // From moved_to_fine's start that bias is out already: the fit is evaluated there (its cost, its
  // Jacobian for the standard errors) and takes no step.
  if (!on_coarse.converged) fine.max_iterations = std::min(fine.max_iterations, kCrawlPolishIterations);
  return judged(lm::fit_lm(with_effect, on_coarse.values, dataset, train, fine, progress), with_effect, effect);
}

Refit refit_with(const model::MotorFile& with_effect, int effect, const ParamVector<double>& start, calibrate::DatasetRef dataset,
                 const std::vector<std::size_t>& train, const lm::LmSettings& settings, const lm::LmProgress& progress,
                 const calibrate::SharedDataset* coarse) {
  if (coarse != nullptr)
    if (const std::optional<lm::LmReport> on_coarse = coarse_stage(with_effect, start, *coarse, train, settings, progress))
      return polish(with_effect, effect, *on_coarse, dataset, train, settings, progress);
  return judged(lm::fit_lm(with_effect, start, dataset, train, settings, progress), with_effect, effect);
}

}  // namespace lptn::diagnose::internal
