// The score test alone: nil along an effect the data does not contain, large along one it does.
#include <gtest/gtest.h>

#include "fixture.hpp"
#include "trainer/diagnose/internal/score_test.hpp"

namespace lptn::diagnose {
namespace {

double windage_score(const testing::Generated& g) {
  const int windage = effect_index("windage");
  MotorFile with = g.motor;
  enable_effect(with, windage);
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

}  // namespace
}  // namespace lptn::diagnose
