// `lptn calibrate`'s arguments, shared by the LM path in lptn and the TD3 path in lptn-td3.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::cli {

struct CalibrateArgs {
  std::vector<std::string> data;
  std::string motor, method = "lm", out, config, checkpoint_dir, fleet, warm_start, map;
  std::vector<std::string> test_cycles, effects;
  std::vector<std::string> sensor_faults;  // SENSOR:SHAPE:SIZE:FIRST, taken out of the readings
  double test_fraction = 1.0 / 3.0;
  std::uint64_t seed = 1;
  int episodes = 0;
  std::size_t budget_steps = 0;  // random-search, cma-es (0: their default)
  bool resume = false, force = false, quiet = false, seed_given = false, test_curve = false;
};

// Runs a TD3 formulation (`args.method`) and writes what it found into `result`. Only lptn-td3
// links libtorch and has one; lptn hands --method td3* over to lptn-td3.
using Td3Calibrator = void (*)(const CalibrateArgs& args, const MotorFile& motor, const data::Dataset& dataset,
                               const Split& split, CalibrationResult& result);

}  // namespace lptn::cli
