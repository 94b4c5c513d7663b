// The readings as a calibration saw them: the sensor faults it was calibrated around (lptn
// calibrate --sensor-fault) taken out of a dump's readings again, so that diagnose, check and
// report compare the model with what the sensor stands for, as the fit did.
#pragma once

#include <string>
#include <vector>

#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn::check {

// Corrects `dataset` for each of the calibration's sensor faults whose first cycle it holds, and
// says what it did in one line each: "readings corrected for the fault the calibration was made
// around: stator:offset:+3.02:cycle_05_freight", or, where the data lacks that cycle, that they
// are compared as they are.
std::vector<std::string> correct_as_calibrated(data::Dataset& dataset, const calibrate::CalibrationResult& calibration);

}  // namespace lptn::check
