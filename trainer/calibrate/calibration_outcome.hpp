// A calibration's outcome: what a user must know before using it, as warnings, and the status
// they add up to (ok, warnings, failed). One judge for every method, so that LM, TD3 and the
// search baselines are held to the same rules (docs/calibration.md, "Status and warnings").
#pragma once

#include <string>
#include <vector>

#include "trainer/calibrate/calibration_file.hpp"

namespace lptn::calibrate {

// Sets result.warnings and result.status from a scored calibration (parameters and metrics set),
// keeping warnings already there (`data_findings`: what inspecting the data found, one line each).
//
// failed:   a parameter or a metric is not finite; or the fit stopped without converging with a
//           parameter on a bound (the optimizer ran into a wall: data and model disagree at the root,
//           e.g. temperatures in the wrong unit or another motor's file)
// warnings: a parameter on a bound; one the data could not pin; not converged; a test error far
//           above the training error; anything the data's inspection found; the model findings
// ok:       none of these
// `model_findings`: warnings about the calibrated model the caller found (the workflow's adequacy:
// the model several times its sensors' noise off), kept as they are.
// `test_vs_train`: whether a test error far above the training error is a warning. A single motor's
// metrics, yes. A fleet's pooled ones are the type's as if one motor had driven every cycle: they
// differ between the splits by which motors' cycles each holds (a weak motor's cycles in the test
// split make the test error 4x the training error on a fleet that is the model exactly), which the
// fleet's outlier test already says, and its adequacy is judged per motor (model_findings).
enum class TestVsTrain { judged, not_judged };
void judge_outcome(CalibrationResult& result, const std::vector<std::string>& data_findings = {},
                   const std::vector<CalibrationWarning>& model_findings = {},
                   TestVsTrain test_vs_train = TestVsTrain::judged);

// One line for a program that goes on to use a calibration whose status is not ok (replay, check,
// diagnose), or empty: a failed one always ("PATH: status failed (failed_fit, at_bound): lptn
// calibrate wrote it for inspection only ..."), one with warnings where `also_warnings` (replay:
// what a converter flashed with it would estimate). The warnings' codes, each once, in order.
std::string status_caution(const CalibrationResult& result, const std::string& path, bool also_warnings);

// Whether a calibrated parameter ended on (or within rounding of) one of its bounds.
bool at_bound(const ParameterResult& p);

}  // namespace lptn::calibrate
