// The header `lptn export` wrote at build time from the fixture, compiled in: every value in it
// equals the calibration's, bit for bit.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <iterator>
#include <type_traits>

#include "thermal_calibration.hpp"
#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::exporter {
namespace {

const calibrate::CalibrationResult& fixture() {
  static const calibrate::CalibrationResult c = calibrate::load_calibration(LPTN_EXPORT_FIXTURE);
  return c;
}

TEST(ExportedHeader, Provenance) {
  const calibrate::CalibrationResult& c = fixture();
  EXPECT_EQ(calibration::kCalibrationFormatVersion, c.format_version);
  EXPECT_STREQ(calibration::kSourceFile, "calibration.json");
  EXPECT_EQ(calibration::kMethod, c.method);
  EXPECT_EQ(calibration::kCreatedUtc, c.created_utc);
  EXPECT_EQ(calibration::kLptnVersion, c.lptn_version);
  EXPECT_EQ(calibration::kMotorName, c.motor.name);  // quotes and UTF-8 survive the escaping
  EXPECT_EQ(calibration::kDataSha256, c.data_sha256);
  EXPECT_EQ(calibration::kTrainRmseStatorK, c.train.stator.rmse_k);
  EXPECT_EQ(calibration::kTestRmseStatorK, c.test.stator.rmse_k);
  EXPECT_TRUE(calibration::kHasTestMetrics);
  EXPECT_EQ(calibration::kHasRotorMetrics, c.test.rotor.samples > 0);
  EXPECT_EQ(calibration::kTestRmseRotorK, c.test.rotor.rmse_k);
  // The fixture's split rule holds a newline followed by "#error": had it escaped the comment, this
  // file would not have compiled.
  EXPECT_NE(c.split_rule.find("\n#error"), std::string::npos);
}

TEST(ExportedHeader, EffectsAndParameters) {
  const calibrate::CalibrationResult& c = fixture();
  EXPECT_EQ(calibration::kEffects, c.effects);
  const ParamVector<double> v = c.values();
  for (int i = 0; i < kNumParams; ++i) EXPECT_EQ(calibration::kParams[i], v[i]) << param_spec(i).name;
  EXPECT_EQ(calibration::kParams[0], 24.1375123456789);  // a value that needs all its digits
}

TEST(ExportedHeader, MotorConstantsEqualTheMotorFile) {
  const MotorConstants<double>& a = fixture().motor.constants;
  constexpr MotorConstants<double> b = calibration::motor_constants();
  int compared = 0;
  for_each_motor_constant(
      [&](const MotorField& f, const auto& exported, const auto& read) {
        if constexpr (std::is_array_v<std::remove_cvref_t<decltype(exported)>>) {
          for (std::size_t i = 0; i < std::size(exported); ++i) EXPECT_EQ(exported[i], read[i]) << f.name << "[" << i << "]";
        } else {
          EXPECT_EQ(exported, read) << f.name;
        }
        ++compared;
      },
      b, a);
  EXPECT_GT(compared, 20);
  EXPECT_EQ(b.min_airflow_fraction, 0.12);  // not the default: the optional key made it through
}

template <std::size_t N>
void expect_floats_eq(const float (&exported)[N], const std::vector<float>& expected, const char* what) {
  ASSERT_EQ(N, expected.size()) << what;
  EXPECT_EQ(std::memcmp(exported, expected.data(), N * sizeof(float)), 0) << what;  // bit for bit
}

TEST(ExportedHeader, ActorEqualsTheCalibrations) {
  const calibrate::ActorExport& a = fixture().actor;
  EXPECT_EQ(calibration::kActor.inputs, 2);
  EXPECT_EQ(calibration::kActor.hidden, a.layers[0].out);
  EXPECT_EQ(calibration::kActor.outputs, a.layers[2].out);
  expect_floats_eq(calibration::kActorW1, a.layers[0].weight, "W1");
  expect_floats_eq(calibration::kActorB1, a.layers[0].bias, "B1");
  expect_floats_eq(calibration::kActorW2, a.layers[1].weight, "W2");
  expect_floats_eq(calibration::kActorB2, a.layers[1].bias, "B2");
  expect_floats_eq(calibration::kActorW3, a.layers[2].weight, "W3");
  expect_floats_eq(calibration::kActorB3, a.layers[2].bias, "B3");
  expect_floats_eq(calibration::kActorCheckObs, a.check_obs, "check_obs");
  expect_floats_eq(calibration::kActorCheckActions, a.check_actions, "check_actions");
  EXPECT_EQ(calibration::kActorChecks * 2, static_cast<int>(a.check_obs.size()));
  ASSERT_EQ(std::size(calibration::kActorParamIndex), a.param_indices.size());
  for (std::size_t j = 0; j < a.param_indices.size(); ++j) {
    EXPECT_EQ(calibration::kActorParamIndex[j], a.param_indices[j]);
    EXPECT_EQ(calibration::kActorParamMin[j], fixture().parameters[a.param_indices[j]].min);
    EXPECT_EQ(calibration::kActorParamMax[j], fixture().parameters[a.param_indices[j]].max);
  }
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(calibration::kActorObsOffset[i], a.obs_offset[i]);
    EXPECT_EQ(calibration::kActorObsScale[i], a.obs_scale[i]);
  }
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(calibration::kActorW2) % 16, 0u);
}

}  // namespace
}  // namespace lptn::exporter
