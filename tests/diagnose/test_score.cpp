// The score test alone: nil along an effect the data does not contain, large along one it does;
// the same whether an effect is scored alone or beside the others from one joint Jacobian; and
// blind to a parameter that does nothing where it is evaluated.
#include <gtest/gtest.h>

#include <cmath>

#include "lptn_testing/small_fleet.hpp"
#include "trainer/diagnose/diagnose.hpp"
#include "trainer/diagnose/internal/score_test.hpp"

namespace lptn::diagnose {
namespace {

double windage_score(const testing::Generated& g) {
  const int windage = effect_index("windage");
  model::MotorFile with = g.motor;
  model::enable_effect(with, windage);
  return internal::score_test(with, windage, g.calibrated, g.dataset, g.split.train, 2).statistic;
}

TEST(ScoreTest, IsSmallWhereTheDataHasNoEffectAndLargeWhereItHasOne) {
  // The hidden-effect suite's short data (six cycles of 25-30 minutes, four training).
  const auto plain = testing::generate({}, 6, 25, 30, 3);
  const auto windy = testing::generate({"windage"}, 6, 25, 30, 3);
  const double threshold = chi_square_quantile(0.999, 1);
  const double absent = windage_score(*plain), present = windage_score(*windy);
  std::printf("windage score: %.2f without, %.1f with windage in the data (threshold %.2f)\n", absent, present, threshold);
  EXPECT_LT(absent, threshold);
  EXPECT_GT(present, 2 * threshold);
}

internal::Score alone(const testing::Generated& g, int effect) {
  model::MotorFile with = g.motor;
  model::enable_effect(with, effect);
  return internal::score_test(with, effect, g.calibrated, g.dataset, g.split.train, 2);
}

// diagnose scores every missing effect with score_tests: those that do nothing at their neutral
// value and add no state from one joint Jacobian. Each must be its score alone, on data where one
// of them (windage) is present, so that the statistics are far from zero.
TEST(ScoreTest, EveryEffectScoredJointlyScoresAsItDoesAlone) {
  const auto g = testing::generate({"windage"}, 6, 25, 30, 3);
  std::vector<int> missing;
  for (int e = 0; e < kNumEffects; ++e)
    if (!(g->motor.effects & effect_bit(e))) missing.push_back(e);
  int joint = 0, scored_alone = 0;
  const std::vector<internal::Score> scores =
      internal::score_tests(g->motor, missing, g->calibrated, g->dataset, g->split.train, 2,
                            [&](int e) { e < 0 ? ++joint : ++scored_alone; });
  ASSERT_EQ(scores.size(), missing.size());
  EXPECT_EQ(joint, 1);
  EXPECT_LT(scored_alone, 10) << "most effects are scored jointly";
  double largest = 0;
  for (std::size_t k = 0; k < missing.size(); ++k) {
    const internal::Score one = alone(*g, missing[k]);
    const auto name = EffectLibrary::kNames[static_cast<std::size_t>(missing[k])];
    EXPECT_EQ(scores[k].feasible, one.feasible) << name;
    EXPECT_NEAR(scores[k].statistic, one.statistic, 1e-6 * std::max(1.0, one.statistic)) << name;
    EXPECT_NEAR(scores[k].rss_k2, one.rss_k2, 1e-9 * one.rss_k2) << name;
    for (int i = 0; i < kNumParams; ++i) {
      if (effect_of_param(i) != missing[k]) continue;
      EXPECT_NEAR(scores[k].predicted[i], one.predicted[i], 1e-6 * std::max(1.0, std::abs(one.predicted[i])))
          << name << " " << param_spec(i).name;
    }
    largest = std::max(largest, one.statistic);
  }
  std::printf("%zu effects, largest score %.1f\n", missing.size(), largest);
  EXPECT_GT(largest, chi_square_quantile(0.999, 1)) << "windage is found: the comparison is not of zeros";
}

// A term's exponent does nothing while its size is zero (the neutral point), so its column of the
// Jacobian is exactly zero there and its score must be that of the size alone, feasibility too.
// The normal equations summed through LM's compressed blocks left rounding noise of 1e-12 in that
// column, which equilibration scaled up to information (heat_stator_core_fluxf scored 7.0 on clean
// data, 2.7 without the noise), and the exponent's nil step made every such term "feasible".
TEST(ScoreTest, AParameterThatDoesNothingAtTheNeutralPointAddsNothing) {
  // 700 W into the stator winding above 50 Hz, which the winding's heat forms point at.
  const auto g = testing::generate({}, 6, 25, 30, 3, {}, gen::plant_bit(gen::PlantPhysics::step_loss));
  int compared = 0;
  double largest = 0;
  for (int e = 0; e < kNumEffects; ++e) {
    const auto name = EffectLibrary::kNames[static_cast<std::size_t>(e)];
    // The heat forms P x^k: a size (W) and an exponent (a step's threshold is not an exponent).
    if (!name.starts_with("heat_") || name.find("_above_") != std::string_view::npos) continue;
    model::MotorFile with = g->motor;
    model::enable_effect(with, e);
    const internal::Score both = internal::score_test(with, e, g->calibrated, g->dataset, g->split.train, 2);
    const int exponent = kNumPaperParams + EffectLibrary::kParamOffsets[static_cast<std::size_t>(e)] + 1;
    with.parameters[static_cast<std::size_t>(exponent)].calibrate = false;
    const internal::Score size = internal::score_test(with, e, g->calibrated, g->dataset, g->split.train, 2);
    EXPECT_EQ(both.feasible, size.feasible) << name;
    EXPECT_NEAR(both.statistic, size.statistic, 1e-6 * std::max(1.0, size.statistic)) << name;
    ++compared;
    largest = std::max(largest, size.statistic);
  }
  std::printf("%d heat forms compared, largest score %.1f\n", compared, largest);
  EXPECT_GE(compared, 16);
  EXPECT_GT(largest, chi_square_quantile(0.999, 1)) << "the step's heat is found: the comparison is not of zeros";
}

}  // namespace
}  // namespace lptn::diagnose
