// The hidden-effect suite: data generated with one effect the paper's model lacks; the paper's
// model calibrated on it; diagnose must point at the effect, and adding it must bring the test
// error down to the sensors' noise. An effect this data cannot separate must be called so.
//
// Which sensor shows an effect: without the air gap the paper's network has no path between
// stator and rotor, so windage, rotor_speed_convection and air_heating change only the rotor's
// temperature (seen by the bench's rotor telemetry), sensor_lag only the stator sensor, airgap
// both. The test error that must halve is that of the sensor further from its noise before.
#include <gtest/gtest.h>

#include <cstdio>

#include "fixture.hpp"

namespace lptn::diagnose {
namespace {

constexpr double kStatorNoiseK = 0.4, kRotorNoiseK = 0.5;  // the generator's sensor model

struct TestErrors {
  double stator, rotor;
};

TestErrors test_errors(const MotorFile& motor, const ParamVector<double>& values, const testing::Generated& g) {
  const SplitMetrics m = evaluate_split(motor.model(), values, g.dataset, g.split.test);
  return {m.stator.rmse_k, m.rotor.rmse_k};
}

void print(const Diagnosis& d) {
  std::printf("  training RMSE %.3f K, test stator %.3f K\n", d.rmse_k, d.test_stator_rmse_k);
  for (const Candidate& c : d.candidates)
    std::printf("  %-24s score %8.1f  LR %8.1f / %.1f  train %.3f -> %.3f K  test stator -> %.3f K  %s %s\n",
                c.name.c_str(), c.score, c.statistic, c.threshold, d.rmse_k, c.refit_rmse_k, c.test_stator_rmse_k,
                to_string(c.verdict), c.reason.c_str());
}

// The effect ranks first and is significant; recalibrated with it (from the motor file's
// starting point, as `lptn calibrate --effect` does), the test error falls to the noise.
void expect_found_and_fixed(const std::string& effect, const testing::Generated& g) {
  const Diagnosis d = diagnose(g.motor, g.calibrated.values, g.dataset, g.split, Settings{});
  print(d);
  ASSERT_FALSE(d.candidates.empty());
  EXPECT_EQ(d.candidates.front().name, effect);
  EXPECT_EQ(d.candidates.front().verdict, Verdict::significant) << d.candidates.front().reason;

  MotorFile with = g.motor;
  enable_effect(with, effect_index(effect));
  const LmReport fit = fit_lm(with, with.initial_values(), g.dataset, g.split.train, LmSettings{});
  const TestErrors before = test_errors(g.motor, g.calibrated.values, g), after = test_errors(with, fit.values, g);
  std::printf("%s: test RMSE stator %.3f -> %.3f K, rotor %.3f -> %.3f K; %s = %.4g +- %.2g\n", effect.c_str(),
              before.stator, after.stator, before.rotor, after.rotor,
              std::string(param_spec(kNumPaperParams + EffectLibrary::kParamOffsets[effect_index(effect)]).name).c_str(),
              fit.values[kNumPaperParams + EffectLibrary::kParamOffsets[effect_index(effect)]],
              fit.std_error[kNumPaperParams + EffectLibrary::kParamOffsets[effect_index(effect)]]);
  EXPECT_LE(after.stator, 2 * kStatorNoiseK);
  EXPECT_LE(after.rotor, 2 * kRotorNoiseK);
  const bool stator_shows = before.stator / kStatorNoiseK > before.rotor / kRotorNoiseK;
  EXPECT_LE(stator_shows ? after.stator : after.rotor, 0.5 * (stator_shows ? before.stator : before.rotor))
      << (stator_shows ? "stator" : "rotor");
}

// Six cycles of 25-30 minutes: every blower mode in the four training cycles, with rotor telemetry.
std::unique_ptr<testing::Generated> short_cycles(const std::string& hidden) {
  return testing::generate({hidden}, 6, 25, 30, 3);
}

TEST(HiddenEffect, Windage) { expect_found_and_fixed("windage", *short_cycles("windage")); }

TEST(HiddenEffect, RotorSpeedConvection) {
  expect_found_and_fixed("rotor_speed_convection", *short_cycles("rotor_speed_convection"));
}

TEST(HiddenEffect, SensorLag) { expect_found_and_fixed("sensor_lag", *short_cycles("sensor_lag")); }

// The air gap's heat flow is largely absorbed by the paper's conductances to air on half-hour
// cycles (test error already near the noise); on cycles of 60-90 minutes stator and rotor drift
// apart long enough that it is not.
TEST(HiddenEffect, Airgap) { expect_found_and_fixed("airgap", *testing::generate({"airgap"}, 6, 60, 90, 3)); }

// Air heating raises the rotor's air by about 0.7 Q_stator / (rho c_p V): a kelvin or two, which
// the rotor's conductance to air absorbs almost exactly even with fixed blower levels in the
// data. Diagnose must say that it cannot tell, and claim nothing else in its place.
TEST(HiddenEffect, AirHeatingIsNotDistinguishableFromThisData) {
  const auto g = short_cycles("air_heating");
  const Diagnosis d = diagnose(g->motor, g->calibrated.values, g->dataset, g->split, Settings{});
  print(d);
  for (const Candidate& c : d.candidates) {
    if (c.name == "air_heating") EXPECT_EQ(c.verdict, Verdict::not_distinguishable);
    else EXPECT_NE(c.verdict, Verdict::significant) << c.name;
  }
}

}  // namespace
}  // namespace lptn::diagnose
