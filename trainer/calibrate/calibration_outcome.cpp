#include "trainer/calibrate/calibration_outcome.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "lptn/params.hpp"

namespace lptn::calibrate {
namespace {

// A test error this many times the training error, and this much above it, means the model
// learnt the training cycles rather than the motor (or the test cycles differ in kind).
constexpr double kTestOverTrainRatio = 2.0;
constexpr double kTestOverTrainMinK = 0.5;

std::string fmt(const char* format, double a, double b = 0, double c = 0) {
  char buf[200];
  std::snprintf(buf, sizeof buf, format, a, b, c);
  return buf;
}

bool finite_metrics(const SplitMetrics& m) {
  auto ok = [](const ErrorMetrics& e) {
    return e.samples == 0 || (std::isfinite(e.rmse_k) && std::isfinite(e.max_abs_k) && std::isfinite(e.bias_k));
  };
  return ok(m.stator) && ok(m.rotor);
}

void compare_test(CalibrationResult& r, const char* sensor, const ErrorMetrics& train, const ErrorMetrics& test) {
  if (train.samples == 0 || test.samples == 0) return;
  if (test.rmse_k > kTestOverTrainRatio * train.rmse_k && test.rmse_k - train.rmse_k > kTestOverTrainMinK)
    r.warnings.push_back({"test_error_high",
                          std::string("the ") + sensor + fmt("'s test RMSE %.2f K is %.1fx its training RMSE %.2f K: the "
                                                             "model fits the training cycles, not the motor, or the test "
                                                             "cycles differ in kind",
                                                             test.rmse_k, test.rmse_k / train.rmse_k, train.rmse_k),
                          {}});
}

}  // namespace

bool at_bound(const ParameterResult& p) {
  if (!p.calibrated) return false;
  // Relative to the range on the scale the calibrators search (log for a positive range).
  const double u = to_normalized(p.value, p.min, p.max);
  return std::abs(u - 1.0) < 1e-6 || std::abs(u + 1.0) < 1e-6;
}

void judge_outcome(CalibrationResult& r, const std::vector<std::string>& data_findings,
                   const std::vector<CalibrationWarning>& model_findings, TestVsTrain test_vs_train) {
  bool failed = false;
  std::vector<std::string> not_finite;
  for (const ParameterResult& p : r.parameters)
    if (!std::isfinite(p.value)) not_finite.push_back(p.name);
  if (!not_finite.empty()) {
    failed = true;
    r.warnings.push_back({"not_finite", "parameters that are not finite numbers", not_finite});
  }
  if (!finite_metrics(r.train) || !finite_metrics(r.test)) {
    failed = true;
    r.warnings.push_back({"not_finite", "the calibrated model's errors are not finite: it runs away on this data", {}});
  }
  std::vector<std::string> bounded;
  for (const ParameterResult& p : r.parameters) {
    if (!at_bound(p)) continue;
    bounded.push_back(p.name);
    const bool low = to_normalized(p.value, p.min, p.max) < 0;
    r.warnings.push_back({"at_bound",
                          p.name + " ended on its " + (low ? "lower" : "upper") + " bound (" + fmt("%g", p.value) + " " +
                              p.unit + "): the data pulls it further; the model or the data is not what the motor file says, "
                                       "and its standard error is local only",
                          {p.name}});
  }
  for (const ParameterResult& p : r.parameters)
    if (!p.identifiable)
      r.warnings.push_back({"not_identifiable", p.name + " is not identifiable from this data: " + p.identifiability, {p.name}});
  const bool converged = !r.details.is_object() || !r.details.contains("converged") || !r.details["converged"].is_boolean() ||
                         r.details["converged"].get<bool>();
  if (!converged) {
    std::string how = r.details.contains("termination") && r.details["termination"].is_string()
                          ? r.details["termination"].get<std::string>()
                          : std::string();
    const int iterations = r.details.contains("iterations") && r.details["iterations"].is_number_integer()
                               ? r.details["iterations"].get<int>()
                               : -1;
    r.warnings.push_back({"not_converged",
                          "the fit did not converge" + (iterations >= 0 ? " in " + std::to_string(iterations) + " iterations" : std::string()) +
                              (how.empty() ? std::string() : " (" + how + ")"),
                          {}});
    if (!bounded.empty()) {
      failed = true;
      r.warnings.push_back({"failed_fit",
                            "the fit stopped without converging against the bounds of its parameters: this data does not "
                            "pin this model (too little of it, temperatures in the wrong unit, or another motor's file?)",
                            bounded});
    }
  }
  if (test_vs_train == TestVsTrain::judged) {
    compare_test(r, "stator winding", r.train.stator, r.test.stator);
    compare_test(r, "rotor", r.train.rotor, r.test.rotor);
  }
  for (const std::string& finding : data_findings) r.warnings.push_back({"data", finding, {}});
  r.warnings.insert(r.warnings.end(), model_findings.begin(), model_findings.end());
  // The fit saw corrected readings; the motor's sensor does not: whatever uses this calibration on
  // board (lptn export, the firmware's observer, which fuses the stator reading) reads it as it is.
  for (const std::string& spec : r.sensor_faults)
    r.warnings.push_back({"sensor_fault",
                          "calibrated around a sensor fault (" + spec + "): the fit saw the readings corrected; the sensor "
                          "itself still reads that way until it is fixed or recalibrated, and on board the observer fuses "
                          "its reading as it is",
                          {}});
  r.status = failed ? kStatusFailed : (r.warnings.empty() ? kStatusOk : kStatusWarnings);
}

std::string status_caution(const CalibrationResult& r, const std::string& path, bool also_warnings) {
  const bool failed = r.status == kStatusFailed;
  if (!failed && !(also_warnings && r.status == kStatusWarnings)) return {};
  std::vector<std::string> codes;
  for (const CalibrationWarning& w : r.warnings)
    if (std::find(codes.begin(), codes.end(), w.code) == codes.end()) codes.push_back(w.code);
  std::string list;
  for (const std::string& c : codes) list += (list.empty() ? "" : ", ") + c;
  return path + ": status " + r.status + (list.empty() ? "" : " (" + list + ")") +
         (failed ? ": lptn calibrate wrote it for inspection only (lptn export refuses it); what follows rests on it"
                 : ": read its warnings (calibration.json's \"warnings\") before trusting what follows");
}

}  // namespace lptn::calibrate
