#include "trainer/diagnose/internal/block_test.hpp"

#include <algorithm>
#include <cmath>
#include <thread>

#include "hostio/worker_threads.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/diagnose/diagnose.hpp"
#include "trainer/diagnose/internal/sensor_traces.hpp"

namespace lptn::diagnose::internal {
namespace {

// The block errors of one cycle: its last block takes the remainder.
std::vector<double> cycle_blocks(const calibrate::CycleEvaluation& e, const data::Cycle& cycle, std::size_t steps_per_block) {
  const std::size_t blocks = std::max<std::size_t>(1, cycle.steps / steps_per_block);
  std::vector<double> out(blocks, 0.0);
  for (const SensorTrace& s : kSensorTraces) {
    const std::vector<float>& model = e.simulation.*s.trace;
    if (!cycle.has(s.channel) || model.size() < cycle.steps) continue;
    for (std::size_t k = 0; k < cycle.steps; ++k) {
      const double r = double(model[k]) - double(cycle.at(s.channel, k));
      if (std::isfinite(r)) out[std::min(blocks - 1, k / steps_per_block)] += r * r;
    }
  }
  return out;
}

}  // namespace

std::size_t block_steps(double correlation_time, double dt_s) {
  const double steps = std::max(kMinBlockSeconds / dt_s, 3.0 * correlation_time);
  return static_cast<std::size_t>(std::ceil(steps));
}

std::vector<double> block_errors(const Model<double>& model, const ParamVector<double>& params,
                                 calibrate::DatasetRef dataset, const std::vector<std::size_t>& cycles,
                                 std::size_t steps_per_block, int threads) {
  std::vector<std::vector<double>> per_cycle(cycles.size());
  hostio::parallel_for(cycles.size(), threads, [&](std::size_t i) {
    const data::Cycle& cycle = dataset.cycles[cycles[i]];
    per_cycle[i] = cycle_blocks(calibrate::simulate_and_evaluate(model, params, cycle), cycle, steps_per_block);
  });
  std::vector<double> out;
  for (const auto& c : per_cycle) out.insert(out.end(), c.begin(), c.end());
  return out;
}

SplitRun run_split(const Model<double>& model, const ParamVector<double>& params, calibrate::DatasetRef dataset,
                   const calibrate::Split& split, std::size_t steps_per_block, int threads) {
  std::vector<std::size_t> every = split.train;
  every.insert(every.end(), split.test.begin(), split.test.end());
  std::vector<std::vector<double>> per_cycle(split.train.size());
  std::vector<calibrate::CycleMetrics> metrics(every.size());
  // Train and test in one loop over the cores (a few cycles keep both busy only together).
  hostio::parallel_for(every.size(), threads, [&](std::size_t i) {
    const data::Cycle& cycle = dataset.cycles[every[i]];
    const calibrate::CycleEvaluation e = calibrate::simulate_and_evaluate(model, params, cycle);
    if (i < per_cycle.size()) per_cycle[i] = cycle_blocks(e, cycle, steps_per_block);
    metrics[i] = e.metrics;
  });
  SplitRun out;
  for (const auto& c : per_cycle) out.train_blocks.insert(out.train_blocks.end(), c.begin(), c.end());
  const auto train_end = metrics.begin() + static_cast<std::ptrdiff_t>(split.train.size());
  out.train.cycles.assign(metrics.begin(), train_end);
  out.test.cycles.assign(train_end, metrics.end());
  calibrate::pool_cycles(out.train);
  calibrate::pool_cycles(out.test);
  return out;
}

BlockTest block_test(const std::vector<double>& before, const std::vector<double>& after, double level) {
  BlockTest b;
  std::vector<double> gains;
  for (std::size_t i = 0; i < before.size() && i < after.size(); ++i)
    if (before[i] > 0 && after[i] > 0) gains.push_back(std::log(before[i] / after[i]));
  b.blocks = static_cast<int>(gains.size());
  if (b.blocks < kMinBlocks) return b;
  double mean = 0, var = 0;
  for (double g : gains) mean += g;
  mean /= b.blocks;
  for (double g : gains) var += (g - mean) * (g - mean);
  var /= b.blocks - 1;
  b.mean_gain = mean;
  b.t = var > 0 ? mean / std::sqrt(var / b.blocks) : (mean > 0 ? INFINITY : 0.0);
  b.threshold = student_t_quantile(1 - level, b.blocks - 1);
  b.significant = b.t > b.threshold;
  return b;
}

}  // namespace lptn::diagnose::internal
