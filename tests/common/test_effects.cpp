// Each effect does what its documentation says, only when enabled, and vanishes at its neutral value.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>

#include "lptn/model.hpp"
#include "lptn_testing/reference_case.hpp"

namespace lptn {
namespace {

struct Outcome {
  double final[kMaxStates];
  double sensor_final;
};

// An hour of a hard cycle from cold: accelerate, run fast, brake, stand.
Outcome run(EffectSet effects, const ParamVector<double>& p) {
  const Model<double> model(testing::example_motor(), effects);
  Outcome r{};
  double x[kMaxStates];
  model.initial_state(x, 20.0, 20.0);
  for (int k = 0; k < 36000; ++k) {
    Inputs<double> in = testing::rated_inputs();
    const double phase = std::fmod(0.1 * k, 900.0);
    in.speed_rpm = phase < 700 ? 3000.0 : 0.0;
    in.current_a = phase < 700 ? 105.0 : 0.0;
    in.frequency_hz = phase < 700 ? 100.5 : 0.0;
    in.torque_nm = phase < 700 ? 950.0 : 0.0;
    in.voltage_v = phase < 700 ? 1900.0 : 0.0;
    in.airflow_m3s = std::fmod(0.1 * k, 2000.0) < 1000 ? 0.5 : 1.0;
    model.step(x, in, p.data(), 0.1);
  }
  for (int i = 0; i < kMaxStates; ++i) r.final[i] = x[i];
  r.sensor_final = model.stator_sensor(x);
  return r;
}

class EachEffect : public ::testing::TestWithParam<int> {};

TEST_P(EachEffect, ChangesTheTemperaturesOnlyWhenEnabled) {
  const int e = GetParam();
  const auto p = default_params<double>();
  const Outcome off = run(0, p), on = run(effect_bit(e), p);
  double change = 0;
  for (int i = 0; i < 4; ++i) change = std::max(change, std::abs(on.final[i] - off.final[i]));
  change = std::max(change, std::abs(on.sensor_final - off.sensor_final));
  EXPECT_GT(change, 0.5) << EffectLibrary::kNames[e];
  // Disabled parameters are ignored entirely.
  auto moved = p;
  for (int i = kNumPaperParams; i < kNumParams; ++i) moved[i] = param_spec(i).max;
  const Outcome off2 = run(0, moved);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(off.final[i], off2.final[i]);
}

TEST_P(EachEffect, VanishesAtItsNeutralValue) {
  const int e = GetParam();
  auto p = default_params<double>();
  for (int k = 0; k < EffectLibrary::kParamCounts[e]; ++k) {
    const int i = kNumPaperParams + EffectLibrary::kParamOffsets[e] + k;
    // A time constant's neutral value is zero; the nearest usable one is far below the step.
    p[i] = param_spec(i).neutral > 0 || param_spec(i).name != "sensor_time_constant_s" ? param_spec(i).neutral : 1e-4;
  }
  const Outcome off = run(0, p), on = run(effect_bit(e), p);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(on.final[i], off.final[i], 1e-6) << EffectLibrary::kNames[e];
  EXPECT_NEAR(on.sensor_final, off.sensor_final, 1e-3) << EffectLibrary::kNames[e];
}

INSTANTIATE_TEST_SUITE_P(Library, EachEffect, ::testing::Range(0, kNumEffects),
                         [](const auto& param_info) { return std::string(EffectLibrary::kNames[param_info.param]); });

TEST(Effects, RotorEffectsLeaveThePaperModelsStatorAlone) {
  // Without a stator-rotor path, rotor-side effects cannot reach the stator.
  const auto p = default_params<double>();
  const Outcome off = run(0, p);
  for (const char* name : {"windage", "air_heating", "rotor_speed_convection"}) {
    const Outcome on = run(effect_bit(effect_index(name)), p);
    EXPECT_EQ(on.final[kStatorWinding], off.final[kStatorWinding]) << name;
    EXPECT_EQ(on.final[kStatorCore], off.final[kStatorCore]) << name;
  }
  EXPECT_GT(run(effect_bit(effect_index("windage")), p).final[kRotorCore], off.final[kRotorCore] + 1.0);
  EXPECT_GT(run(effect_bit(effect_index("air_heating")), p).final[kRotorWinding], off.final[kRotorWinding] + 1.0);
  EXPECT_LT(run(effect_bit(effect_index("rotor_speed_convection")), p).final[kRotorWinding], off.final[kRotorWinding] - 1.0);
}

TEST(Effects, AirgapCarriesHeatFromTheHotterSide) {
  const auto p = default_params<double>();
  const Outcome off = run(0, p), on = run(effect_bit(effect_index("airgap")), p);
  const bool stator_hotter = off.final[kStatorCore] > off.final[kRotorCore];
  EXPECT_EQ(on.final[kStatorCore] < off.final[kStatorCore], stator_hotter);
  EXPECT_EQ(on.final[kRotorCore] > off.final[kRotorCore], stator_hotter);
}

// The sensor follows node 1 through a first-order lag: compare with that lag applied exactly
// (exponential filter at a fine step) to the node's own trajectory.
TEST(Effects, SensorLagIsAFirstOrderLagOfTheWinding) {
  const Model<double> model(testing::example_motor(), effect_bit(effect_index("sensor_lag")));
  auto p = default_params<double>();
  const double tau = 45.0;
  p[param_index("sensor_time_constant_s")] = tau;
  double x[kMaxStates];
  model.initial_state(x, 20.0, 20.0);
  EXPECT_EQ(model.num_states(), 5);
  double filtered = x[0], worst = 0, largest_lag = 0;
  const double dt = 0.1;
  for (int k = 0; k < 6000; ++k) {
    Inputs<double> in = testing::rated_inputs();
    in.current_a = (k / 1000) % 2 ? 20.0 : 140.0;  // heat and cool in turns
    const double before = x[0];
    model.step(x, in, p.data(), dt);
    // Exact lag of a linearly interpolated input over the step.
    const double a = std::exp(-dt / tau), slope = (x[0] - before) / dt;
    filtered = a * filtered + (1 - a) * before + slope * (dt - tau * (1 - a));
    worst = std::max(worst, std::abs(model.stator_sensor(x) - filtered));
    largest_lag = std::max(largest_lag, std::abs(model.stator_sensor(x) - x[0]));
  }
  EXPECT_LT(worst, 0.02);
  EXPECT_GT(largest_lag, 1.0);
}

// A step switches on above its threshold and does nothing below it: the cycle runs at 1.55 of the
// rated frequency and 0.91 of the rated current. Five step widths away it is off (or on) to within
// 1 %; the smooth step stays finite for every ratio, in float too.
TEST(Effects, AStepHeatsAboveItsThresholdOnly) {
  for (const char* name : {"heat_stator_winding_above_f", "heat_rotor_core_above_i"}) {
    const int e = effect_index(name);
    ASSERT_GE(e, 0) << name;
    const int size = kNumPaperParams + EffectLibrary::kParamOffsets[static_cast<std::size_t>(e)];
    const double ratio = std::string_view(name).ends_with("_f") ? 100.5 / testing::example_motor().rated_frequency_hz
                                                                 : 105.0 / testing::example_motor().rated_current_a;
    auto p = default_params<double>();
    p[size] = 800.0;
    const Outcome off = run(0, p);
    p[size + 1] = ratio + 5 * terms::forms::kStepWidth;
    const Outcome above = run(effect_bit(e), p);
    p[size + 1] = ratio - 5 * terms::forms::kStepWidth;
    const Outcome below = run(effect_bit(e), p);
    const int node = EffectLibrary::kNodes[static_cast<std::size_t>(e)];
    const double rise = below.final[node] - off.final[node];
    EXPECT_GT(rise, 1.0) << name;
    EXPECT_LT(std::abs(above.final[node] - off.final[node]), 0.01 * rise) << name;
  }
  // Both steps are one template; what a user reads of each is its own quantity's.
  EXPECT_EQ(EffectLibrary::kFormulas[static_cast<std::size_t>(effect_index("heat_rotor_core_above_i"))],
            "P_r s((I/I_r - x)/0.03)");
  EXPECT_EQ(param_spec(param_index("heat_stator_winding_above_f_threshold")).description,
            "the frequency it switches on above, as a share of the rated frequency");
  EXPECT_EQ(EffectLibrary::kSummaries[static_cast<std::size_t>(effect_index("heat_rotor_core_above_i"))],
            "extra heat in the rotor core switching on above a current");
  using terms::forms::smooth_step;
  EXPECT_EQ((smooth_step<double, double>(0.77, 0.77)), 0.5);
  EXPECT_EQ((smooth_step<float, float>(1e6f, 0.05f)), 1.0f);
  EXPECT_GT((smooth_step<float, float>(0.0f, 2.0f)), 0.0f);
}

// A cooling term on both sides is the stator's and the rotor's twins at the same value.
TEST(Effects, ACoolingTermOnBothSidesIsBothSidesTermsAtOnce) {
  for (const char* family : {"airflow_%s_exponent", "cooling_%s_speed"}) {
    char both[64], stator[64], rotor[64];
    std::snprintf(both, sizeof both, family, "both");
    std::snprintf(stator, sizeof stator, family, "stator");
    std::snprintf(rotor, sizeof rotor, family, "rotor");
    auto p = default_params<double>();
    for (const char* name : {both, stator, rotor}) {
      const int first = kNumPaperParams + EffectLibrary::kParamOffsets[static_cast<std::size_t>(effect_index(name))];
      p[first] = std::string_view(family).starts_with("airflow") ? -0.3 : 0.4;
      if (EffectLibrary::kParamCounts[static_cast<std::size_t>(effect_index(name))] > 1) p[first + 1] = 1.5;
    }
    const Outcome one = run(effect_bit(effect_index(both)), p);
    const Outcome two = run(effect_bit(effect_index(stator)) | effect_bit(effect_index(rotor)), p);
    const Outcome off = run(0, p);
    for (int i = 0; i < kNumNodes; ++i) {
      EXPECT_NEAR(one.final[i], two.final[i], 1e-9) << both << " node " << i;
      EXPECT_GT(std::abs(one.final[i] - off.final[i]), 0.5) << both << " node " << i;
    }
  }
}

}  // namespace
}  // namespace lptn
