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

// fit_lm of `with_effect` (the calibrated motor with `effect` switched on) from `start`: the
// baseline's values with the effect's at one of diagnose's starts (the score test's Gauss-Newton
// step, or the neutral value: from the step alone, or from the motor file's initial guess, a refit
// of a few iterations can end worse than the baseline; diagnose.cpp keeps the better of the two).
Refit refit_with(const MotorFile& with_effect, int effect, const ParamVector<double>& start, const data::Dataset& dataset,
                 const std::vector<std::size_t>& train, const LmSettings& settings, const LmProgress& progress);

}  // namespace lptn::diagnose::internal
