#include "trainer/calibrate/problem.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <thread>

#include "hostio/bad_input.hpp"
#include "trainer/calibrate/shared_dataset.hpp"
#include "trainer/model/initial_offsets.hpp"
#include "trainer/model/simulate.hpp"

namespace lptn::calibrate {

FreeParameters FreeParameters::from_motor(const MotorFile& motor) {
  FreeParameters f;
  for (int i = 0; i < kNumParams; ++i) {
    const ParameterSetting& s = motor.parameters[static_cast<std::size_t>(i)];
    if (!s.calibrate) continue;
    // A parameter of an effect the model does not have cannot be seen in the data.
    const int effect = effect_of_param(i);
    if (effect >= 0 && !(motor.effects & effect_bit(effect))) continue;
    f.index.push_back(i);
    f.min.push_back(s.min);
    f.max.push_back(s.max);
    f.log_scale.push_back(uses_log_scale(s.min, s.max));
  }
  return f;
}

double FreeParameters::to_internal(std::size_t j, double value) const {
  return log_scale[j] ? std::log(value) : value;
}

double FreeParameters::to_physical(std::size_t j, double internal) const {
  return log_scale[j] ? std::exp(internal) : internal;
}

double FreeParameters::slope(std::size_t j, double value) const { return log_scale[j] ? value : 1.0; }

Split split_cycles(const data::Dataset& dataset, const std::vector<std::string>& test_names, double test_fraction,
                   std::uint64_t seed) {
  const std::size_t n = dataset.cycles.size();
  Split split;
  std::vector<bool> is_test(n, false);
  if (!test_names.empty()) {
    for (const std::string& name : test_names) {
      std::size_t found = n;
      for (std::size_t i = 0; i < n; ++i)
        if (dataset.cycles[i].name == name) found = i;
      if (found == n) {
        std::string known;
        for (const data::Cycle& c : dataset.cycles) known += (known.empty() ? "" : ", ") + c.name;
        throw hostio::BadInput("--test-cycles: no cycle named '" + name + "' in the data (cycles: " + known + ")");
      }
      is_test[found] = true;
    }
    split.rule = "--test-cycles";
    for (const std::string& name : test_names) split.rule += (&name == &test_names.front() ? " " : ",") + name;
  } else {
    if (!(test_fraction >= 0.0 && test_fraction < 1.0))
      throw hostio::BadInput("--test-fraction: must be in [0, 1), got " + std::to_string(test_fraction));
    auto count = static_cast<std::size_t>(std::lround(test_fraction * static_cast<double>(n)));
    if (test_fraction > 0 && n >= 2) count = std::clamp<std::size_t>(count, 1, n - 1);
    std::vector<std::size_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = i;
    std::mt19937_64 rng(seed);
    std::shuffle(order.begin(), order.end(), rng);
    for (std::size_t i = 0; i < count; ++i) is_test[order[i]] = true;
    char rule[96];
    std::snprintf(rule, sizeof rule, "fraction %.3g, seed %llu", test_fraction, static_cast<unsigned long long>(seed));
    split.rule = rule;
  }
  for (std::size_t i = 0; i < n; ++i) (is_test[i] ? split.test : split.train).push_back(i);
  if (split.train.empty()) throw hostio::BadInput("the split leaves no cycle to train on");
  return split;
}

namespace {
// Every cycle's metrics on every process of a shared dataset: each slot filled where its cycle is
// held, zero elsewhere, summed over the processes.
void join_metrics(std::vector<CycleMetrics>& metrics, DatasetRef dataset, const std::vector<std::size_t>& cycles) {
  constexpr std::size_t kFields = 5;
  std::vector<double> sums(metrics.size() * 2 * kFields, 0.0);
  for (std::size_t i = 0; i < metrics.size(); ++i) {
    if (dataset.remote(cycles[i])) continue;
    const ErrorMetrics* sides[2] = {&metrics[i].stator, &metrics[i].rotor};
    for (std::size_t s = 0; s < 2; ++s) {
      double* at = sums.data() + (2 * i + s) * kFields;
      at[0] = sides[s]->rmse_k;
      at[1] = sides[s]->mean_abs_k;
      at[2] = sides[s]->max_abs_k;
      at[3] = sides[s]->bias_k;
      at[4] = static_cast<double>(sides[s]->samples);
    }
  }
  dataset.group().sum(sums);
  for (std::size_t i = 0; i < metrics.size(); ++i) {
    metrics[i].name = dataset.cycles[cycles[i]].name;
    ErrorMetrics* sides[2] = {&metrics[i].stator, &metrics[i].rotor};
    for (std::size_t s = 0; s < 2; ++s) {
      const double* at = sums.data() + (2 * i + s) * kFields;
      *sides[s] = {at[0], at[1], at[2], at[3], static_cast<std::size_t>(at[4])};
    }
  }
}
}  // namespace

CycleEvaluation simulate_and_evaluate(const Model<double>& model, const ParamVector<double>& params,
                                      const data::Cycle& cycle, const PreparedCycle* prepared) {
  CycleEvaluation e;
  e.simulation = simulate_cycle(model, params, cycle,
                                estimate_initial_offsets(model, params, cycle, kInitialOffsetWindowS, prepared), prepared);
  e.metrics.name = cycle.name;
  e.metrics.stator = compare(e.simulation.stator_sensor, cycle, data::Channel::stator_winding_c);
  e.metrics.rotor = compare(e.simulation.rotor_sensor, cycle, data::Channel::rotor_c);
  return e;
}

std::size_t evaluation_steps(const data::Cycle& cycle) {
  const auto window = static_cast<std::size_t>(kInitialOffsetWindowS / cycle.dt_s) + 1;
  return 3 * std::min(cycle.steps, window) + cycle.steps;
}

CycleMetrics evaluate_cycle(const Model<double>& model, const ParamVector<double>& params, const data::Cycle& cycle,
                            const PreparedCycle* prepared) {
  // simulate_and_evaluate's metrics, compared as the model runs: the same sums in the same order
  // (a test holds the bits equal), without storing six float series of every step. The time is
  // the model's steps either way (the 48 h drift stage took 1.9 s with it as without); the memory is not.
  ErrorSum stator, rotor;
  std::size_t k = 0;
  run_cycle(model, params.data(), cycle, [&](std::ptrdiff_t, const double* x) {
    if (k >= cycle.steps) return;  // an empty cycle: its initial state alone, nothing to compare
    stator.add(static_cast<float>(model.stator_sensor(x)), cycle.at(data::Channel::stator_winding_c, k));
    rotor.add(static_cast<float>(model.rotor_sensor(x)), cycle.at(data::Channel::rotor_c, k));
    ++k;
  }, estimate_initial_offsets(model, params, cycle, kInitialOffsetWindowS, prepared), SIZE_MAX, prepared);
  CycleMetrics m;
  m.name = cycle.name;
  m.stator = stator.metrics();
  m.rotor = rotor.metrics();
  return m;
}

SplitMetrics evaluate_split(const Model<double>& model, const ParamVector<double>& params, DatasetRef dataset,
                            const std::vector<std::size_t>& cycles, int threads) {
  SplitMetrics out;
  out.cycles.resize(cycles.size());
  // Cycles are independent: each thread writes only its own slots. A remote cycle is its process's.
  hostio::parallel_for(cycles.size(), threads, [&](std::size_t i) {
    if (!dataset.remote(cycles[i])) out.cycles[i] = evaluate_cycle(model, params, dataset.cycles[cycles[i]]);
  });
  if (dataset.shared()) join_metrics(out.cycles, dataset, cycles);
  pool_cycles(out);
  return out;
}

void pool_cycles(SplitMetrics& m) {
  std::vector<ErrorMetrics> stator, rotor;
  for (const CycleMetrics& c : m.cycles) {
    stator.push_back(c.stator);
    if (c.rotor.samples) rotor.push_back(c.rotor);
  }
  m.stator = pool(stator);
  m.rotor = pool(rotor);
}

}  // namespace lptn::calibrate
