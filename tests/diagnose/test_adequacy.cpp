// The verdict on the model itself (trainer/diagnose/adequacy.hpp): a sensor's RMSE against its own
// noise, the noise estimated from the residual, not assumed. On data the calibrated model can
// describe it must say adequate, seed after seed (its false alarms, measured); where the plant
// has physics the model lacks it must say which sensor misses it, and stop saying so once the
// model has it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "lptn_testing/small_fleet.hpp"
#include "trainer/diagnose/adequacy.hpp"
#include "trainer/model/motor_effects.hpp"

namespace lptn::diagnose {
namespace {

const diagnose::SensorAdequacy* sensor(const diagnose::Adequacy& a, const std::string& name) {
  for (const diagnose::SensorAdequacy& s : a.sensors)
    if (s.sensor == name) return &s;
  return nullptr;
}

// Five seeds of clean data (no hidden effect): the paper's model, calibrated, is adequate on
// both sensors, and its noise estimates are the generator's sensor noise (0.4 K stator, 0.5 K rotor).
TEST(Adequacy, CleanDataIsAdequateOverSeeds) {
  int false_alarms = 0;
  double worst_ratio = 0;
  for (std::uint64_t seed = 31; seed < 36; ++seed) {
    const auto g = testing::generate({}, 5, 20, 25, seed);
    const diagnose::Adequacy a =
        diagnose::assess_adequacy(g->motor.model(), g->calibrated.values, g->dataset, g->split, 2);
    ASSERT_EQ(a.sensors.size(), 2u);
    const auto* st = sensor(a, "stator");
    const auto* rt = sensor(a, "rotor");
    ASSERT_TRUE(st && rt);
    EXPECT_NEAR(st->noise_k, 0.4, 0.05) << seed;
    EXPECT_NEAR(rt->noise_k, 0.5, 0.06) << seed;
    for (const auto* s : {st, rt})
      worst_ratio = std::max({worst_ratio, s->train_rmse_k / s->noise_k, s->test_rmse_k / s->noise_k});
    false_alarms += a.adequate ? 0 : 1;
    std::printf("seed %llu: %s | %s\n", static_cast<unsigned long long>(seed), diagnose::describe(*st).c_str(),
                diagnose::describe(*rt).c_str());
  }
  std::printf("clean data: %d false alarms in 5 seeds; largest RMSE/noise %.2f (bound %.1f)\n", false_alarms,
              worst_ratio, diagnose::kAdequateRatio);
  EXPECT_EQ(false_alarms, 0);
  EXPECT_LT(worst_ratio, diagnose::kAdequateRatio);
}

// Windage in the plant, not in the model: the rotor misses it and says so, naming the test cycles;
// the stator, which the paper's network does not link to the rotor, stays adequate. With windage
// in the model the verdict turns.
TEST(Adequacy, NamesTheSensorThatMissesPhysicsAndTurnsOnceTheModelHasIt) {
  const auto g = testing::generate({"windage"}, 6, 25, 30, 3);
  const Model<double> paper = g->motor.model();
  const diagnose::Adequacy before = diagnose::assess_adequacy(paper, g->calibrated.values, g->dataset, g->split, 2);
  const auto* rotor = sensor(before, "rotor");
  const auto* stator = sensor(before, "stator");
  ASSERT_TRUE(rotor && stator);
  std::printf("without windage: %s | %s\n", diagnose::describe(*stator).c_str(), diagnose::describe(*rotor).c_str());
  EXPECT_FALSE(before.adequate);
  EXPECT_FALSE(rotor->adequate);
  EXPECT_TRUE(stator->adequate);
  EXPECT_GT(rotor->unexplained, 0.5);
  ASSERT_FALSE(rotor->cycles.empty());
  // Where: windage heats the rotor with speed squared, so the model runs too cold at speed.
  EXPECT_EQ(rotor->where.region.rfind("high speed", 0), 0u) << rotor->where.region;
  EXPECT_GT(rotor->where.region_rmse_k, rotor->train_rmse_k);
  bool follows_speed = false;
  for (const diagnose::Follows& f : rotor->where.follows)
    follows_speed = follows_speed || (f.input == "speed" && f.correlation < -0.3);
  EXPECT_TRUE(follows_speed) << diagnose::describe(*rotor);
  EXPECT_NE(diagnose::to_json(before).dump().find("\"adequate\":false"), std::string::npos);

  model::MotorFile with = g->motor;
  model::enable_effect(with, effect_index("windage"));
  const lm::LmReport fit = lm::fit_lm(with, with.initial_values(), g->dataset, g->split.train, lm::LmSettings{});
  const diagnose::Adequacy after = diagnose::assess_adequacy(with.model(), fit.values, g->dataset, g->split, 2);
  std::printf("with windage: %s | %s\n", diagnose::describe(*sensor(after, "stator")).c_str(),
              diagnose::describe(*sensor(after, "rotor")).c_str());
  EXPECT_TRUE(after.adequate);
  EXPECT_LT(sensor(after, "rotor")->test_rmse_k, rotor->test_rmse_k / 2);
}

}  // namespace
}  // namespace lptn::diagnose
