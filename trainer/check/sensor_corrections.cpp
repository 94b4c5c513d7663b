#include "trainer/check/sensor_corrections.hpp"

#include <stdexcept>

#include "trainer/data/sensor_fault.hpp"

namespace lptn::check {

std::vector<std::string> correct_as_calibrated(data::Dataset& dataset, const calibrate::CalibrationResult& calibration) {
  std::vector<std::string> said;
  for (const std::string& spec : calibration.sensor_faults) {
    const data::SensorFaultSpec parsed = data::parse_sensor_fault(spec);  // load_calibration checked it
    data::SensorFault fault;
    try {
      fault = data::resolve(parsed, dataset);
    } catch (const hostio::BadInput&) {
      // A dump without the fault's first cycle (another period's, another motor's): which of its
      // cycles the fault touches is unknown.
      said.push_back("the calibration was made around the sensor fault " + spec +
                     ", whose first cycle is not in this data: its readings are compared as they are");
      continue;
    }
    data::correct_readings(dataset, fault);
    said.push_back("readings corrected for the sensor fault the calibration was made around: " + spec);
  }
  return said;
}

}  // namespace lptn::check
