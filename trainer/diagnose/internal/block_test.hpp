// The block test: significance that holds when the residuals are strongly correlated.
//
// The likelihood ratio counts n_eff = residuals / correlation time independent residuals. Where
// the model is badly wrong, the correlation time is the model error's, minutes long, and the count
// says little either way. The block test does not lean on it: the training cycles are cut into
// blocks of at least kMinBlockSeconds and three correlation times, so that blocks are close to
// independent (the refit's correlation time: see diagnose.cpp), and each block's gain is
// ln(SSE before / SSE after) over its measured sensors. The
// effect is significant when the mean gain is positive beyond the one-sided Student t quantile at
// the diagnosis's level with blocks - 1 degrees of freedom. Fewer than kMinBlocks blocks decide
// nothing (not significant).
#pragma once

#include <cstddef>
#include <vector>

#include "lptn/model.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn::diagnose::internal {

inline constexpr double kMinBlockSeconds = 300;
inline constexpr int kMinBlocks = 4;

// Each block's squared error (both sensors), over `cycles` in order.
std::vector<double> block_errors(const Model<double>& model, const ParamVector<double>& params,
                                 calibrate::DatasetRef dataset, const std::vector<std::size_t>& cycles,
                                 std::size_t block_steps, int threads);

// One simulation of each cycle of the split at `params`: the training cycles' block errors (as
// block_errors gives them) and every cycle's metrics, pooled per side as evaluate_split pools them.
struct SplitRun {
  std::vector<double> train_blocks;
  calibrate::SplitMetrics train, test;
};
SplitRun run_split(const Model<double>& model, const ParamVector<double>& params, calibrate::DatasetRef dataset,
                   const calibrate::Split& split, std::size_t block_steps, int threads);

// Grid steps per block for residuals of this correlation time (in grid steps) on grid step dt.
std::size_t block_steps(double correlation_time, double dt_s);

struct BlockTest {
  int blocks = 0;
  double mean_gain = 0;  // mean of ln(SSE before / SSE after)
  double t = 0;          // its t statistic
  double threshold = 0;  // the Student t quantile it must exceed
  bool significant = false;
};

BlockTest block_test(const std::vector<double>& before, const std::vector<double>& after, double level);

}  // namespace lptn::diagnose::internal
