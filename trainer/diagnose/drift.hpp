// Drift between cycles: has the motor changed over the dump?
//
// A fleet dump spans weeks. A filter clogs, a blower weakens, a sensor is replaced: the later
// cycles then differ from the earlier ones, and no physical effect explains that. Calibrated on
// all of them, an effect would absorb the change and be recommended for the wrong reason. So,
// before any candidate: per cycle, the factor of one parameter group that fits that cycle best
// (the others held at the calibration), and whether those factors change across the dump.
//
//   groups     cooling: every conductance to air (lambda_1s, lambda_2s, lambda_1r, lambda_2r)
//              times c; losses: both copper-loss factors (k_stemp, k_rtemp) times c. The cooling
//              is tried first; the losses only where the cooling shows no change.
//   per cycle  c minimizing the cycle's squared error over its measured sensors (on log c: a
//              parabola through factor 1 and a step to either side, refined through its vertex;
//              Brent's minimizer over the whole range where those do not bracket it; offsets
//              estimated per cycle as the metrics do).
//   the test   y_i = log c_i in the dump's order (the cycles sorted by file name). Step: the
//              largest two-sample t statistic over every split with at least two cycles on each
//              side. Trend: the t statistic of the least-squares slope. Each statistic's p-value
//              is exact under "no drift" (the cycles exchangeable): the share of 4,000 random
//              orderings that reach it. A drift is found when p <= kDriftLevel and the change is
//              at least kMinDriftChange; the second guards against a change the model's own
//              misfit between kinds of cycle could make. With fewer than eight cycles, no ordering
//              can reach the level and nothing is found.
//
// A drift is a finding, not an effect: while one is found, diagnose recommends nothing.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lptn/model.hpp"
#include "trainer/calibrate/metrics.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn::diagnose {

inline constexpr double kDriftLevel = 0.05;
inline constexpr double kMinDriftChange = 0.10;

enum class DriftGroup { cooling, losses };
const char* to_string(DriftGroup g);

struct CycleFactor {
  std::string cycle;
  double factor = 1;
};

struct Drift {
  DriftGroup group = DriftGroup::cooling;
  std::vector<CycleFactor> factors;  // every cycle, in the dump's order
  bool found = false;
  std::string shape;                 // "step" or "trend" (the more significant)
  double p_value = 1;
  double change = 0;                 // relative: changed cycles' factor over the others', minus one
  std::vector<std::string> cycles;   // the changed cycles (after the step; the later half of a trend)
  std::string finding;               // e.g. "the cooling of cycles a..b is 29 % weaker than the rest's"
  std::string inspect;               // what to look at
};

// Cooling first; where it shows no drift, the losses. `params` is the calibration; `at_params`,
// one per cycle of `dataset` where given, the cycle's evaluate_cycle metrics at `params` where the
// caller has them already (null: simulated here).
Drift find_drift(const Model<double>& model, const ParamVector<double>& params, const data::Dataset& dataset,
                 int threads, const std::vector<const calibrate::CycleMetrics*>& at_params = {});

// `params` with the group's parameters times `factor`.
ParamVector<double> scaled_group(const ParamVector<double>& params, DriftGroup group, double factor);

// {"group", "found", "shape", "p_value", "change", "cycles", "finding", "inspect",
//  "factors": [{"cycle", "factor"}]}
nlohmann::json to_json(const Drift& drift);

}  // namespace lptn::diagnose
