// `--method td3`, `td3-paper` and `td3-episode` as a CalibrationMethod: train_td3 with the
// request's settings, and what it found, as calibration.json records it (the set, the training
// curve, the agent kept for a warm start, the actor to flash where the formulation has one).
#pragma once

#include "trainer/calibrate/calibration_request.hpp"

namespace lptn::td3 {

// The request's TD3 fields: td3_config (else the formulation's defaults; the seed wins over the
// file's where given), episodes, checkpoint_dir (else OUT.checkpoints), resume, warm_start (an
// earlier td3 calibration of the same free parameters and bounds, its agent beside it, checked by
// hash: BadInput naming the field otherwise) and test_curve. The agent is kept beside the output
// as OUT.agent, written before the output is.
void calibrate_td3(const calibrate::CalibrationRequest& request, const MotorFile& motor, calibrate::DatasetRef dataset,
                   const calibrate::Split& split, calibrate::CalibrationResult& result, const calibrate::CalibrationProgress& progress);

}  // namespace lptn::td3
