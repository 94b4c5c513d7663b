// An LM fit as calibration.json records it, for `lptn calibrate --method lm` and for the refits
// `lptn diagnose --auto` writes out: one builder, so that the two files say the same things.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/calibrate/calibration_request.hpp"
#include "trainer/lm/lm.hpp"

namespace lptn::lm {

// The settings as method.settings records them.
nlohmann::json to_json(const LmSettings& settings);

// Writes `fit` into `result`: every parameter's value and standard error, the correlated pairs,
// method "lm" with `settings`, the fit's details (iterations, cost, correlation, parameters at a
// bound, the initial offsets of the `fitted` cycles, named in the order fit_lm was given them) and
// its wall time. The metrics are score_calibration's to set.
void record_lm_fit(calibrate::CalibrationResult& result, const LmReport& fit, const calibrate::FreeParameters& free,
                   const std::vector<std::string>& fitted, nlohmann::json settings);

// Marks each listed parameter as the data could not pin it: not calibrated, not identifiable,
// with its reason (record_lm_fit for LM's own judgement; calibrate for the other methods').
void mark_not_identifiable(calibrate::CalibrationResult& result, const std::vector<NotIdentifiable>& parameters);

// `--method lm` (a CalibrationMethod): fit_lm from the motor file's initial values, judging what
// the data cannot pin (it stays the motor file's, said so), recorded by record_lm_fit. Progress:
// "lm: iteration N  rmse X K  m:ss".
void calibrate_lm(const calibrate::CalibrationRequest& request, const MotorFile& motor, calibrate::DatasetRef dataset,
                  const calibrate::Split& split, calibrate::CalibrationResult& result, const calibrate::CalibrationProgress& progress);

}  // namespace lptn::lm
