// A calibration from request to result, the whole of it: the motor file and its added effects,
// the data (through its map, the sensor faults taken out), the split, what inspecting data and
// motor file finds, what the data cannot pin, the method, the metrics and the outcome. The caller
// (lptn calibrate; a binding, a service) fills in the request, hears of the work through the
// events, and saves and prints the result.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "hostio/process_group.hpp"
#include "trainer/calibrate/calibration_request.hpp"
#include "trainer/fleet/fleet_calibration.hpp"

namespace lptn::workflow {

// The work as it begins: what is fitted on what.
struct CalibrationPlan {
  std::string motor_name, method;
  std::size_t train_cycles = 0, test_cycles = 0;
  std::string split_rule;  // how the test cycles were chosen
  std::size_t motors = 0;  // a fleet's; 0 for one motor's data
};

struct CalibrationEvents {
  // What `lptn inspect --motor` would say of this data and motor file, once, before the work
  // (every process of an MPI job hears it; lptn prints the first's).
  std::function<void(const std::vector<std::string>& warnings)> input_warnings;
  std::function<void(const CalibrationPlan& plan)> started;
  calibrate::CalibrationProgress progress;
};

// The methods by name (--method). TD3's formulations run where a program that links libtorch gives
// their CalibrationMethod.
inline constexpr std::array<std::string_view, 6> kMethods = {"lm", "td3", "td3-paper", "td3-episode", "random-search", "cma-es"};
bool is_method(const std::string& name);
bool is_td3(const std::string& method);

// The processes a method's work is shared over: LM's over the MPI job, if one started this
// program; every other method's alone (each rank would train the same agent).
const hostio::ProcessGroup& calibration_group(const std::string& method);

// The request's own arguments, before any file is read: the method (known, runnable here: `td3`
// null refuses the TD3 formulations), MPI (only LM is shared), the effects' names, the options
// that go together (--fleet with LM, a sensor fault without it, a warm start or test curve with
// td3). BadInput naming the option.
void check_request(const calibrate::CalibrationRequest& request, calibrate::CalibrationMethod td3 = nullptr);

// Calibrates one motor's data (request.data). The result is scored on both sides of the split and
// judged (status, warnings); the caller saves it (save_calibration) where its process group leads.
// BadInput for input that cannot be calibrated (an unreadable file, a motor the model cannot
// simulate, naming its most implausible value); other exceptions for failures of the machine.
calibrate::CalibrationResult calibrate(const calibrate::CalibrationRequest& request, const CalibrationEvents& events = {},
                            calibrate::CalibrationMethod td3 = nullptr);

// A fleet (request.fleet): the motor type over every motor, each motor's cooling factor, the
// outliers. `result` is the pooled calibration (the type, scored as if one motor had driven every
// cycle); fleet::save_fleet writes the three together.
struct FleetCalibration {
  calibrate::CalibrationResult result;
  fleet::FleetFit fit;
  fleet::FleetSettings settings;
  std::size_t cycles = 0;  // every motor's
};
FleetCalibration calibrate_fleet(const calibrate::CalibrationRequest& request, const CalibrationEvents& events = {});

}  // namespace lptn::workflow
