// A fleet of one motor type calibrated as a whole: the type's shared parameters, and each motor's
// deviation from them (its cooling factor), with the motors that cool unlike the rest named.
//
// The fit is hierarchical by alternation: the shared parameters by Levenberg-Marquardt over every
// motor's training cycles, each cycle simulated with its motor's cooling factor; then each motor's
// factor against them (cooling_factor_fit.hpp); the factors are normalized so that the fleet's
// median motor has 1 (the shared conductances to air absorb the scale: a factor and the shared
// conductances are only known as a product). Rounds repeat until no factor moves by more than
// round_tolerance. A joint fit rather than per-motor fits shrunk toward the pool: the shared
// parameters are fitted once on all the data, free of the scatter that per-motor fits of every
// parameter would each carry, and the factor is what the fleet is asked about.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "trainer/lm/lm.hpp"
#include "trainer/fleet/cooling_factor_fit.hpp"
#include "trainer/fleet/fleet_dump.hpp"
#include "trainer/fleet/outlier_test.hpp"

namespace lptn::fleet {

struct FleetSettings {
  lm::LmSettings lm;
  int max_rounds = 6;
  double round_tolerance = 1e-3;  // on ln(factor)
  double family_alpha = 0.05;     // chance that a fleet without outliers names one (outlier_test.hpp)
};

struct FleetMotorResult {
  std::string id;
  double cooling_factor = 1;
  double cooling_factor_std = 0;  // factor * the standard error of ln(factor)
  CoolingFactorFit fit;
  ParamVector<double> parameters{};  // the shared ones with this motor's cooling factor
  calibrate::SplitMetrics metrics;              // on all the motor's cycles
  OutlierVerdict verdict;
};

struct FleetFit {
  lm::LmReport shared;  // the motor type: the parameters of the fleet's median motor
  std::vector<FleetMotorResult> motors;  // in FleetDump order
  int rounds = 0;
  double log_factor_spread = 0;  // standard deviation of the motors' ln(factor)
  double seconds = 0;
};

// `train`: the cycles (indices into fleet.dataset) the shared fit uses. `progress` gets a line per
// step.
FleetFit fit_fleet(const MotorFile& motor, const FleetDump& fleet, const std::vector<std::size_t>& train,
                   const FleetSettings& settings, const std::function<void(const std::string&)>& progress = {});

}  // namespace lptn::fleet
