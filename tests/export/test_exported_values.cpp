// The header `lptn export` wrote at build time from the fixture, compiled in: every value in it
// equals the calibration's, bit for bit.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <iterator>

#include "thermal_calibration.hpp"
#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn {
namespace {

const CalibrationResult& fixture() {
  static const CalibrationResult c = load_calibration(LPTN_EXPORT_FIXTURE);
  return c;
}

TEST(ExportedHeader, Provenance) {
  const CalibrationResult& c = fixture();
  EXPECT_EQ(calibration::kCalibrationFormatVersion, c.format_version);
  EXPECT_STREQ(calibration::kSourceFile, "calibration.json");
  EXPECT_EQ(calibration::kMethod, c.method);
  EXPECT_EQ(calibration::kCreatedUtc, c.created_utc);
  EXPECT_EQ(calibration::kLptnVersion, c.lptn_version);
  EXPECT_EQ(calibration::kMotorName, c.motor_name);  // quotes and UTF-8 survive the escaping
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
  const CalibrationResult& c = fixture();
  EXPECT_EQ(calibration::kEffects, c.effects);
  const ParamVector<double> v = c.values();
  for (int i = 0; i < kNumParams; ++i) EXPECT_EQ(calibration::kParams[i], v[i]) << param_spec(i).name;
  EXPECT_EQ(calibration::kParams[0], 24.1375123456789);  // a value that needs all its digits
}

TEST(ExportedHeader, MotorConstantsEqualTheMotorFile) {
  const MotorConstants<double> a = parse_motor_file(fixture().motor_text, "motor.text").constants;
  constexpr MotorConstants<double> b = calibration::motor_constants();
  EXPECT_EQ(b.pole_pairs, a.pole_pairs);
  EXPECT_EQ(b.rated_frequency_hz, a.rated_frequency_hz);
  EXPECT_EQ(b.rated_voltage_v, a.rated_voltage_v);
  EXPECT_EQ(b.rated_current_a, a.rated_current_a);
  EXPECT_EQ(b.rated_power_w, a.rated_power_w);
  EXPECT_EQ(b.stator_resistance_20c_ohm, a.stator_resistance_20c_ohm);
  EXPECT_EQ(b.stator_resistance_alpha_per_k, a.stator_resistance_alpha_per_k);
  EXPECT_EQ(b.rotor_resistance_20c_ohm, a.rotor_resistance_20c_ohm);
  EXPECT_EQ(b.rotor_resistance_alpha_per_k, a.rotor_resistance_alpha_per_k);
  EXPECT_EQ(b.magnetizing_current_a, a.magnetizing_current_a);
  EXPECT_EQ(b.stray_rated_w, a.stray_rated_w);
  EXPECT_EQ(b.iron_rated_w, a.iron_rated_w);
  EXPECT_EQ(b.iron_alpha, a.iron_alpha);
  EXPECT_EQ(b.iron_beta, a.iron_beta);
  EXPECT_EQ(b.harmonic_points, a.harmonic_points);
  for (int i = 0; i < kMaxHarmonicPoints; ++i) {
    EXPECT_EQ(b.harmonic_frequency_hz[i], a.harmonic_frequency_hz[i]) << i;
    EXPECT_EQ(b.harmonic_loss_w[i], a.harmonic_loss_w[i]) << i;
  }
  for (int i = 0; i < 4; ++i) EXPECT_EQ(b.capacitance_j_per_k[i], a.capacitance_j_per_k[i]) << i;
  EXPECT_EQ(b.nominal_airflow_m3s, a.nominal_airflow_m3s);
  EXPECT_EQ(b.airflow_exponent, a.airflow_exponent);
  EXPECT_EQ(b.min_airflow_fraction, a.min_airflow_fraction);
  EXPECT_EQ(b.min_airflow_fraction, 0.12);  // not the default: the optional key made it through
}

template <std::size_t N>
void expect_floats_eq(const float (&exported)[N], const std::vector<float>& expected, const char* what) {
  ASSERT_EQ(N, expected.size()) << what;
  EXPECT_EQ(std::memcmp(exported, expected.data(), N * sizeof(float)), 0) << what;  // bit for bit
}

TEST(ExportedHeader, ActorEqualsTheCalibrations) {
  const ActorExport& a = fixture().actor;
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
}  // namespace lptn
