// docs/effects.md's how-to, followed as written: this test is compiled against the effect library
// the document's two code blocks make (extract_howto.py, at build time), with the model, the data
// generator, the calibration and the diagnosis built against it. A bearing loss hidden in the data
// must be found by diagnose, ranked above windage (a square law in speed, where the bearing's is
// linear), and fitted: its size recovered and the test error halved.
#include <gtest/gtest.h>

#include <cmath>

#include "lptn_testing/hidden_effect_check.hpp"
#include "trainer/diagnose/internal/heat_path.hpp"

namespace lptn::diagnose {
namespace {

constexpr double kTrueBearingLossW = 800.0;

TEST(EffectHowTo, TheDocumentsBearingLossIsRegisteredAfterTheLibrarysEffects) {
  const int e = effect_index("bearing_loss");
  ASSERT_EQ(e, EffectLibrary::kCount - 1);
  EXPECT_EQ(param_index("bearing_loss_w"), kNumParams - 1);  // appended: every other index kept
  EXPECT_EQ(param_spec(param_index("bearing_loss_w")).neutral, 0.0);
}

// What the header declares for a diagnosis is what the diagnosis uses: nothing else was written.
TEST(EffectHowTo, TheDiagnosisReadsTheHeadersKnowledge) {
  const int e = effect_index("bearing_loss");
  EXPECT_EQ(EffectLibrary::kNeeds[static_cast<std::size_t>(e)], effects::BearingLoss::kNeeds);
  // A rotor-side loss: a stator conductance has no heat path to it, a rotor one has.
  EXPECT_FALSE(internal::shares_heat_path(kLambda12s, e, effect_bit(e)));
  EXPECT_TRUE(internal::shares_heat_path(kLambda1r, e, effect_bit(e)));
  // No kScoreAt: NaN, the score test at the neutral value.
  EXPECT_TRUE(std::isnan(EffectLibrary::kScoreAt[static_cast<std::size_t>(e)]));
}

TEST(EffectHowTo, BearingLossHiddenInTheDataIsFoundAndFitted) {
  const auto g = testing::generate({"bearing_loss"}, 6, 25, 30, 3, {{"bearing_loss_w", kTrueBearingLossW}});
  lm::LmReport fit;
  expect_found_and_fixed("bearing_loss", *g, &fit);
  const int p = param_index("bearing_loss_w");
  std::printf("bearing_loss_w = %.1f +- %.1f W (truth %.0f)\n", fit.values[p], fit.std_error[p], kTrueBearingLossW);
  // Recovered to within a few per cent: the paper's conductances are fitted at the same time.
  EXPECT_NEAR(fit.values[p], kTrueBearingLossW, 0.05 * kTrueBearingLossW);
}

}  // namespace
}  // namespace lptn::diagnose
