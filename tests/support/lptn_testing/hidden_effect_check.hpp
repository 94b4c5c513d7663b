// The hidden-effect check shared by the library's suite and the how-to's test: diagnose must rank
// the hidden effect first and call it significant; recalibrated with it (from the motor file's
// starting point, as `lptn calibrate --effect` does), the test error must halve and end within
// twice the sensors' noise.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "lptn_testing/small_fleet.hpp"
#include "lptn_testing/sound_candidates.hpp"
#include "trainer/diagnose/diagnose.hpp"

namespace lptn::diagnose {

constexpr double kStatorNoiseK = 0.4, kRotorNoiseK = 0.5;  // the generator's sensor model

struct TestErrors {
  double stator, rotor;
};

inline TestErrors test_errors(const MotorFile& motor, const ParamVector<double>& values, const testing::Generated& g) {
  const calibrate::SplitMetrics m = calibrate::evaluate_split(motor.model(), values, g.dataset, g.split.test);
  return {m.stator.rmse_k, m.rotor.rmse_k};
}

inline void print(const Diagnosis& d) {
  std::printf("  training RMSE %.3f K, test stator %.3f K\n", d.rmse_k, d.test_stator_rmse_k);
  for (const Candidate& c : d.candidates)
    std::printf("  %-24s score %8.1f  LR %8.1f / %.1f  train %.3f -> %.3f K  test stator -> %.3f K  %s %s\n",
                c.name.c_str(), c.score, c.statistic, c.threshold, d.rmse_k, c.refit_rmse_k, c.test_stator_rmse_k,
                to_string(c.verdict), c.reason.c_str());
}

// The effect ranks first and is significant; recalibrated with it (from the motor file's
// starting point, as `lptn calibrate --effect` does), the test error falls to the noise. The refit
// is handed back through `refit` for checks of its own.
inline void expect_found_and_fixed(const std::string& effect, const testing::Generated& g, lm::LmReport* refit = nullptr) {
  const Diagnosis d = diagnose(g.motor, g.calibrated.values, g.dataset, g.split, Settings{});
  print(d);
  expect_sound_candidates(d, effect);
  ASSERT_FALSE(d.candidates.empty());
  EXPECT_EQ(d.candidates.front().name, effect);
  EXPECT_EQ(d.candidates.front().verdict, Verdict::significant) << d.candidates.front().reason;

  MotorFile with = g.motor;
  enable_effect(with, effect_index(effect));
  const lm::LmReport fit = lm::fit_lm(with, with.initial_values(), g.dataset, g.split.train, lm::LmSettings{});
  if (refit) *refit = fit;
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

}  // namespace lptn::diagnose
