// lptn check: does a calibration still hold on this data, or must the motor be recalibrated?
//
// Per cycle, with the calibration's parameters (offsets estimated per cycle as its metrics are):
//   error    each measured sensor's RMSE against the sensor's noise (estimated from the residual
//            at its readings over every cycle given, as lptn diagnose does: adequacy.hpp) and
//            against the calibration's own test error for that sensor. A cycle's sensor is beyond
//            its bound when RMSE > max(kAdequateRatio x noise, kOverCalibrationError x the
//            calibration's test error): a calibration that fitted its sensors to their noise is
//            held to diagnose's adequacy; one that already missed something (the paper's model on
//            a motor with windage: the rotor 8 K off) is held to what it claimed, not condemned for
//            the misfit it declared.
//   cooling  the cycle's cooling factor (every conductance to the air times c, the others at the
//            calibration: trainer/fleet/cooling_factor_fit.hpp; 1 = as calibrated) with its
//            standard error. It has changed when |ln c| >= ln(1 + kMinCoolingChange) and
//            |ln c| > kCoolingZ standard errors: the size guards against what the model's own
//            misfit between kinds of cycle can make (as drift.hpp's kMinDriftChange), the
//            significance against a short cycle's scatter.
// The calibration holds when every cycle does and the data's motor constants (its motor.toml, if
// any) are the calibration's. docs/check.md gives the thresholds' reasons and the measured rates.
#pragma once

#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/check/provenance.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/diagnose/adequacy.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::check {

inline constexpr double kOverCalibrationError = 2.0;
inline constexpr double kMinCoolingChange = 0.10;
inline constexpr double kCoolingZ = 3.0;

struct SensorCheck {
  bool measured = false;
  double rmse_k = std::numeric_limits<double>::quiet_NaN();
  double over_noise = std::numeric_limits<double>::quiet_NaN();        // rmse / the sensor's noise
  double over_calibration = std::numeric_limits<double>::quiet_NaN();  // rmse / the calibration's test error
  bool beyond = false;                                                // beyond its bound
};

struct CycleCheck {
  std::string name;
  CycleProvenance provenance;
  SensorCheck sensors[2];  // stator, rotor
  double cooling_factor = 1;
  double cooling_log_std_error = 0;
  bool cooling_changed = false;
  bool holds = true;
};

struct Check {
  bool holds = true;
  std::vector<std::string> reasons;  // why not, in words; empty where it holds
  diagnose::Adequacy adequacy;       // every cycle given, at the calibration's parameters
  // The calibration's own test error per sensor (its training error without test cycles), NaN
  // where it did not measure the sensor.
  double calibration_error_k[2] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  double noise_k[2] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  std::vector<CycleCheck> cycles;    // in the dataset's order
  double cooling_factor = 1;         // every cycle together (inverse-variance mean of the cycles' ln c)
  double cooling_log_std_error = 0;
  Provenance provenance;
};

inline constexpr const char* kSensorNames[2] = {"stator", "rotor"};

// `calibration`'s model (motor_of) at its values on `dataset`. `data_motor`: the motor file found
// beside the data, compared with the calibration's constants.
Check check(const calibrate::CalibrationResult& calibration, const data::Dataset& dataset,
            const std::optional<MotorFile>& data_motor, int threads);

// {"holds", "reasons", "adequate", "adequate_within", "sensors" (diagnose's shape, over every cycle
// given), "thresholds", "calibration_error_k", "cooling_factor", "cooling_factor_std_log",
// "data": {"never_seen", "constants", "summary"}, "cycles": [{"name", "holds", "seen", "role",
// "stator_rmse_k", "rotor_rmse_k", "stator_over_noise", ..., "cooling_factor", "cooling_changed"}]}
nlohmann::json to_json(const Check& check);

// The verdict for a terminal: a table per cycle, the sensors as diagnose judges them, the reasons.
std::string describe(const Check& check);

}  // namespace lptn::check
