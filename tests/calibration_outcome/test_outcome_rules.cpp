// judge_outcome's rules, one at a time: each warning, and the status the warnings add up to.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "trainer/calibrate/calibration_outcome.hpp"

namespace lptn::calibrate {
namespace {

// A calibration that is fine in every respect: two calibrated conductances well inside their
// bounds, a converged LM fit, test errors like the training ones.
calibrate::CalibrationResult fine() {
  calibrate::CalibrationResult r;
  for (const char* name : {"lambda_1s", "lambda_2s"}) {
    calibrate::ParameterResult p;
    p.name = name;
    p.unit = "W/K";
    p.value = 30;
    p.initial = 40;
    p.min = 1;
    p.max = 1000;
    p.calibrated = true;
    p.std_error = 0.1;
    r.parameters.push_back(p);
  }
  r.details = {{"converged", true}, {"iterations", 5}, {"termination", "Function tolerance reached."}};
  r.train.stator = {0.35, 0.28, 1.5, 0.0, 1000};
  r.test.stator = {0.37, 0.29, 1.6, 0.05, 500};
  return r;
}

bool has_code(const calibrate::CalibrationResult& r, const std::string& code) {
  for (const calibrate::CalibrationWarning& w : r.warnings)
    if (w.code == code) return true;
  return false;
}

TEST(OutcomeRules, FineIsOk) {
  calibrate::CalibrationResult r = fine();
  calibrate::judge_outcome(r);
  EXPECT_EQ(r.status, calibrate::kStatusOk);
  EXPECT_TRUE(r.warnings.empty());
}

TEST(OutcomeRules, AParameterOnItsBoundIsAWarning) {
  for (double value : {1.0, 1000.0, 1000.0 * (1 - 1e-9)}) {
    calibrate::CalibrationResult r = fine();
    r.parameters[0].value = value;
    calibrate::judge_outcome(r);
    EXPECT_EQ(r.status, calibrate::kStatusWarnings) << value;
    ASSERT_TRUE(has_code(r, "at_bound")) << value;
    EXPECT_EQ(r.warnings[0].parameters, std::vector<std::string>{"lambda_1s"});
    EXPECT_NE(r.warnings[0].message.find(value < 2 ? "lower bound" : "upper bound"), std::string::npos);
  }
  // Near a bound but not on it: no warning.
  calibrate::CalibrationResult r = fine();
  r.parameters[0].value = 1.01;
  calibrate::judge_outcome(r);
  EXPECT_EQ(r.status, calibrate::kStatusOk);
}

TEST(OutcomeRules, APinnedParameterOnItsBoundIsNoWarning) {
  calibrate::CalibrationResult r = fine();
  r.parameters[1].calibrated = false;  // the motor file pins it, at whatever value it likes
  r.parameters[1].value = 1000;
  calibrate::judge_outcome(r);
  EXPECT_EQ(r.status, calibrate::kStatusOk);
}

TEST(OutcomeRules, NotIdentifiableIsAWarningWithItsReason) {
  calibrate::CalibrationResult r = fine();
  r.parameters[1].calibrated = false;
  r.parameters[1].identifiable = false;
  r.parameters[1].identifiability = "no rotor readings";
  calibrate::judge_outcome(r);
  EXPECT_EQ(r.status, calibrate::kStatusWarnings);
  ASSERT_TRUE(has_code(r, "not_identifiable"));
  EXPECT_NE(r.warnings[0].message.find("no rotor readings"), std::string::npos);
}

TEST(OutcomeRules, NotConvergedIsAWarningAndWithABoundAFailure) {
  calibrate::CalibrationResult r = fine();
  r.details["converged"] = false;
  calibrate::judge_outcome(r);
  EXPECT_EQ(r.status, calibrate::kStatusWarnings);
  EXPECT_TRUE(has_code(r, "not_converged"));

  calibrate::CalibrationResult f = fine();
  f.details["converged"] = false;
  f.parameters[0].value = 1.0;
  calibrate::judge_outcome(f);
  EXPECT_EQ(f.status, calibrate::kStatusFailed);
  EXPECT_TRUE(has_code(f, "failed_fit"));
}

TEST(OutcomeRules, NonFiniteIsAFailure) {
  calibrate::CalibrationResult r = fine();
  r.train.stator.rmse_k = std::numeric_limits<double>::infinity();
  calibrate::judge_outcome(r);
  EXPECT_EQ(r.status, calibrate::kStatusFailed);
  EXPECT_TRUE(has_code(r, "not_finite"));

  calibrate::CalibrationResult p = fine();
  p.parameters[0].value = std::nan("");
  calibrate::judge_outcome(p);
  EXPECT_EQ(p.status, calibrate::kStatusFailed);
}

TEST(OutcomeRules, ATestErrorFarAboveTrainingIsAWarning) {
  calibrate::CalibrationResult r = fine();
  r.test.stator.rmse_k = 5.4;  // the motor with a thermal mass the model lacks: 5.0x
  calibrate::judge_outcome(r);
  EXPECT_EQ(r.status, calibrate::kStatusWarnings);
  EXPECT_TRUE(has_code(r, "test_error_high"));
  // Twice a small training error but within half a kelvin of it: noise, not overfitting.
  calibrate::CalibrationResult small = fine();
  small.train.stator.rmse_k = 0.2;
  small.test.stator.rmse_k = 0.5;
  calibrate::judge_outcome(small);
  EXPECT_EQ(small.status, calibrate::kStatusOk);
}

// A fleet's pooled metrics are the type's as if one motor had driven every cycle: not compared.
TEST(OutcomeRules, AFleetsTestErrorIsNotComparedWithItsTraining) {
  calibrate::CalibrationResult r = fine();
  r.test.stator.rmse_k = 5.4;
  calibrate::judge_outcome(r, {}, {}, calibrate::TestVsTrain::not_judged);
  EXPECT_EQ(r.status, calibrate::kStatusOk);
}

TEST(OutcomeRules, ModelFindingsAreWarningsAsTheyAre) {
  calibrate::CalibrationResult r = fine();
  calibrate::judge_outcome(r, {}, {{"not_adequate", "the model is not adequate on the stator sensor: ...", {}}});
  EXPECT_EQ(r.status, calibrate::kStatusWarnings);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0].code, "not_adequate");
}

// What replay, check and diagnose say before they use a calibration: a failed one always, one with
// warnings where asked, each code once; nothing for an ok one.
TEST(OutcomeRules, AStatusCautionNamesTheStatusAndItsCodes) {
  calibrate::CalibrationResult ok = fine();
  calibrate::judge_outcome(ok);
  EXPECT_EQ(calibrate::status_caution(ok, "cal.json", true), "");
  calibrate::CalibrationResult warned = fine();
  warned.parameters[0].value = 1.0;
  warned.parameters[1].value = 1.0;
  calibrate::judge_outcome(warned, {}, {{"not_adequate", "the model is not adequate on the stator sensor: ...", {}}});
  EXPECT_EQ(calibrate::status_caution(warned, "cal.json", false), "");
  EXPECT_EQ(calibrate::status_caution(warned, "cal.json", true).rfind("cal.json: status warnings (at_bound, not_adequate): read", 0), 0u)
      << calibrate::status_caution(warned, "cal.json", true);
  calibrate::CalibrationResult failed = fine();
  failed.parameters[0].value = 1.0;
  failed.parameters[1].value = 1.0;
  failed.details["converged"] = false;
  calibrate::judge_outcome(failed);
  ASSERT_EQ(failed.status, calibrate::kStatusFailed);
  const std::string caution = calibrate::status_caution(failed, "cal.json", false);
  EXPECT_EQ(caution.rfind("cal.json: status failed (at_bound, not_converged, failed_fit", 0), 0u) << caution;
  EXPECT_NE(caution.find("for inspection only"), std::string::npos) << caution;
}

TEST(OutcomeRules, DataFindingsAreWarnings) {
  calibrate::CalibrationResult r = fine();
  calibrate::judge_outcome(r, {"cycle_01.csv: pole pairs: the motor file says 3, the data's speed and frequency say 2"});
  EXPECT_EQ(r.status, calibrate::kStatusWarnings);
  EXPECT_TRUE(has_code(r, "data"));
}

}  // namespace
}  // namespace lptn::calibrate
