// The one place a calibration file's content is put together, whichever calibrator ran: the frame
// before it runs (provenance, motor, parameters, data, split), the metrics after, and the way back
// from a file to the motor and split it was made with.
#pragma once

#include <string>

#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::calibrate {

// Parameter i as the motor file starts a calibration: name, unit, initial value (also the value
// until a calibrator sets one), bounds, and whether it is calibrated (an effect's parameter only
// where the motor has the effect).
ParameterResult parameter_result(const MotorFile& motor, int i);

// A calibration before its calibrator has run: created now by this lptn, the motor (`motor_path`
// as given), every parameter at its start, the data's files and hashes, the split.
CalibrationResult new_calibration(const MotorFile& motor, const std::string& motor_path, DatasetRef dataset,
                                  const Split& split);

// Sets the train and test metrics of `result`'s parameters on its split (model from its motor).
void score_calibration(CalibrationResult& result, const MotorFile& motor, DatasetRef dataset,
                       const Split& split);

// The motor a calibration was made with: its stored text, its effects, and the parameters'
// bounds and calibrate flags as the calibration used them.
MotorFile motor_of(const CalibrationResult& calibration);

// The calibration's own train/test split, found by cycle name in `dataset`; throws
// BadInput naming a cycle the data lacks.
Split split_of(const CalibrationResult& calibration, const data::Dataset& dataset);

}  // namespace lptn::calibrate
