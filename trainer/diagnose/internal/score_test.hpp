// The score (Lagrange multiplier) test of one effect: no fit, one Jacobian at the calibrated
// parameters with the effect at its neutral value.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "trainer/lm/lm.hpp"

namespace lptn::diagnose::internal {

struct Score {
  double statistic = 0;     // g' (J'J)^-1 g / (s^2 tau): chi-square with df = the effect's parameters under "absent"
  double reduction_k2 = 0;  // g' (J'J)^-1 g: the fall of the RSS one Gauss-Newton step predicts
  double rss_k2 = 0;        // at the evaluation point
  std::size_t residuals = 0;
  // Whether the Gauss-Newton step moves the effect into its bounds. Where it does not, the data
  // pull the effect below its neutral value: the constrained fit stays there (to first order) and
  // the likelihood ratio is 0, so no refit is needed.
  bool feasible = false;
  ParamVector<double> predicted{};  // the calibrated values with the effect's where the step puts them
};

// The calibrated values with the effect's parameters where it does nothing (or, for a neutral value
// the model cannot take, where its notes say): where the score is evaluated.
ParamVector<double> neutral_point(const ParamVector<double>& calibrated, int effect);

// `with_effect` is the calibrated motor with `effect` switched on; `baseline` the fit of the
// model without it (values, per-cycle offsets, RSS, correlation time) on `train`.
Score score_test(const MotorFile& with_effect, int effect, const lm::LmReport& baseline, calibrate::DatasetRef dataset,
                 const std::vector<std::size_t>& train, int threads);

// The score tests of `effects` (none of them in `motor`), in their order: those that leave the
// model as it was at their neutral values and add no state from one joint Jacobian, the others one
// by one; each score as score_test gives it (to the rounding of a wider sum). `scoring` hears of
// each effect scored alone, and of the joint evaluation as -1.
std::vector<Score> score_tests(const MotorFile& motor, const std::vector<int>& effects, const lm::LmReport& baseline,
                               calibrate::DatasetRef dataset, const std::vector<std::size_t>& train, int threads,
                               const std::function<void(int)>& scoring = {});

}  // namespace lptn::diagnose::internal
