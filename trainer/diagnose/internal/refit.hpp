// The refit with one effect added, and whether the data can tell the effect apart.
#pragma once

#include <string>
#include <vector>

#include "trainer/calibrate/lm.hpp"

namespace lptn::diagnose::internal {

// Why the refit cannot pin the effect, as sentence fragments naming the parameter (empty: it can).
struct Refit {
  LmReport fit;
  std::string confounded;  // correlated beyond the flag with a parameter the model has: a property of the data
  std::string imprecise;   // a standard error beyond the value (or none at all)
};

// `fine`'s cycles on a grid `factor` times coarser (data::coarse_grid: the 1 s grid TD3 scores on
// at 10), shared over the processes as `fine` is (each remote cycle's residual count its own).
data::Dataset coarse_dataset(const data::Dataset& fine, int factor);

// fit_lm of `with_effect` (the calibrated motor with `effect` switched on) from `start`: the
// baseline's values with the effect's at one of diagnose's starts (the score test's Gauss-Newton
// step, or the neutral value: from the step alone, or from the motor file's initial guess, a refit
// of a few iterations can end worse than the baseline; diagnose.cpp keeps the better of the two).
// With `coarse` (coarse_dataset of `dataset`): the fit first runs there, a tenth of the work per
// iteration, and then on `dataset` from where it ended (its parameters and the cycles' initial
// offsets), where it polishes: the result is the fit on `dataset`, and its iterations are the
// polish's. Where the data pin the effect the polish takes a few iterations to the same optimum;
// along a flat direction (an absent effect) it may end elsewhere on it than a fit without the
// coarse stage (README, "Scale: a fleet dump of 200 hours"). Without a reading on the coarse
// grid, the fine fit alone.
Refit refit_with(const MotorFile& with_effect, int effect, const ParamVector<double>& start, const data::Dataset& dataset,
                 const std::vector<std::size_t>& train, const LmSettings& settings, const LmProgress& progress,
                 const data::Dataset* coarse = nullptr);

}  // namespace lptn::diagnose::internal
