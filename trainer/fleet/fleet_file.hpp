// fleet.json: a fleet calibration (docs/fleet.md has the keys).
//   "pooled":  the motor type's calibration, in the shape of calibration.json (the parameters of
//              the fleet's median motor; its metrics as if one motor had driven every cycle);
//   "fleet":   how the fleet was fitted and tested (rounds, spread, the outlier test);
//   "motors":  {"<id>": {"parameters": [...], "metrics": {...}, "cooling_factor": x,
//               "cooling_factor_std": s, "outlier": bool, "reason": "..."}}.
#pragma once

#include <cstddef>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/fleet/fleet_calibration.hpp"

namespace lptn::fleet {

inline constexpr int kFleetFormatVersion = 1;

nlohmann::ordered_json fleet_json(const calibrate::CalibrationResult& pooled, const FleetFit& fit, const FleetSettings& settings);
// Atomic, as save_calibration.
void save_fleet(const std::filesystem::path& path, const calibrate::CalibrationResult& pooled, const FleetFit& fit,
                const FleetSettings& settings);

struct FleetFileMotor {
  std::string id;
  ParamVector<double> parameters{};
  double cooling_factor = 1, cooling_factor_std = 0;
  bool outlier = false;
  std::string reason;
  double t = std::numeric_limits<double>::quiet_NaN();  // the outlier test's statistic; NaN if not tested
  std::size_t cycles = 0;
  double rmse_stator_k = 0;
  double rmse_rotor_k = std::numeric_limits<double>::quiet_NaN();  // NaN where the rotor is not measured
};

struct FleetFile {
  calibrate::CalibrationResult pooled;
  std::vector<FleetFileMotor> motors;
  double threshold_t = std::numeric_limits<double>::quiet_NaN();  // NaN: too few motors to test
  double family_alpha = 0;
  int rounds = 0;
};

// Throws CalibrationFileError: "FILE: field 'motors.motor_03.cooling_factor': reason".
FleetFile load_fleet_file(const std::filesystem::path& path);

// One motor as a calibration of its own (for lptn export): the pooled calibration with the
// motor's parameters. Throws BadInput naming the known ids for an unknown one.
calibrate::CalibrationResult motor_calibration(const FleetFile& fleet, const std::string& id);

}  // namespace lptn::fleet
