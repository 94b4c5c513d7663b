// The firmware's estimator configured from a calibration.json (the host's way; the firmware's is
// the header `lptn export` writes, firmware/include/lptn/firmware/exported_calibration.hpp). Both
// give the same EstimatorConfig: the same parameters, motor constants, effects and actor.
#pragma once

#include <memory>
#include <vector>

#include "lptn/firmware/estimator_config.hpp"
#include "trainer/calibrate/calibration_file.hpp"

namespace lptn::replay {

// The configuration and what its actor view points into (the weights live here, not in a header).
struct CalibratedEstimatorConfig {
  fw::EstimatorConfig<double> config;
  std::vector<float> weights[3], biases[3];
  std::vector<int> param_index;
  std::vector<double> param_min, param_max;
  ActorView actor_view{};
};

// Throws MotorFileError if the embedded motor text does not parse, CalibrationFileError if the
// actor's shape is not the firmware's (3 dense layers, at most 256 hidden units, 32 outputs).
// `bus`: the converter's frames (default: the bus map the firmware was built for, lptn::bus).
std::unique_ptr<CalibratedEstimatorConfig> estimator_config_from(const calibrate::CalibrationResult& calibration,
                                                                  const std::string& shown_as,
                                                                  const fw::BusDecoder& bus = lptn::bus::decoder());

}  // namespace lptn::replay
