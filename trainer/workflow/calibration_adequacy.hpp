// Whether a calibrated model is the motor: each measured sensor's error against its noise, estimated
// from its own readings (diagnose's adequacy), judged into the calibration's not_adequate warnings.
// A model several times its sensors' noise off lacks physics the motor has, or its method stopped
// short of the best fit; either way a user must hear it before flashing it.
#pragma once

#include <vector>

#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/fleet/fleet_calibration.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::workflow {

// How far above its noise a sensor's RMSE may be before the calibration warns. Looser than
// diagnose's 1.5x (diagnose/adequacy.hpp), which asks the finer question: at twice the noise the
// model's own error is 1.7x the noise (sqrt(2^2 - 1)), beyond what a right model keeps on short data
// with split cycles (1.6x on three 15-minute cycles, each with a 6-minute dropout, tests/data).
inline constexpr double kCalibrationAdequateRatio = 2.0;

// Scores a single motor's calibration (result.train and result.test, as score_calibration does, to
// the bit) and returns its not_adequate warnings, one per sensor beyond the ratio, worded with
// where the residual is largest. Alone the check is the scoring's own simulation; shared over an MPI
// job's processes, one more simulation of each process's cycles, and the warning says how far off,
// not where (that needs every cycle on one process).
std::vector<calibrate::CalibrationWarning> score_and_judge_adequacy(calibrate::CalibrationResult& result, const model::MotorFile& motor,
                                                         calibrate::DatasetRef dataset, const calibrate::Split& split);

// A fleet's: each motor's cycles run with its own cooling factor (fit.motors[m].parameters), its
// RMSE over them (fit.motors[m].metrics) against the fleet's sensors' noise; one warning per motor
// and sensor beyond the ratio. One more simulation of every cycle (each process its own).
std::vector<calibrate::CalibrationWarning> fleet_adequacy(const model::MotorFile& motor, const fleet::FleetDump& fleet,
                                               const fleet::FleetFit& fit);

}  // namespace lptn::workflow
