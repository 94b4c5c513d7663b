// diagnose's refits take their steps on the 1 s grid and polish on the data's own (refit.hpp):
// where the data pin the effect they end where a refit on the data's grid alone ends, and where
// the coarse grid keeps no reading (a sensor sampled off the 1 s instants) the fine refit runs
// alone instead of failing.
#include <gtest/gtest.h>

#include <cmath>

#include "fixture.hpp"
#include "trainer/diagnose/internal/refit.hpp"

namespace lptn::diagnose {
namespace {

constexpr int kCoarse = 10;  // diagnose's factor: 1 s on 10 Hz data

TEST(CoarseRefit, EndsWhereTheFineRefitEndsWhereTheDataPinTheEffect) {
  const auto g = testing::generate({"windage"}, 4, 20, 25, 5);
  const int windage = effect_index("windage");
  MotorFile with = g->motor;
  enable_effect(with, windage);
  LmSettings lm;
  lm.threads = 2;
  const data::Dataset coarse = internal::coarse_dataset(g->dataset, kCoarse);
  const auto fine = internal::refit_with(with, windage, g->calibrated.values, g->dataset, g->split.train, lm, {});
  const auto staged = internal::refit_with(with, windage, g->calibrated.values, g->dataset, g->split.train, lm, {}, &coarse);
  const int w = param_index("windage_base_w");
  std::printf("windage_base_w %.2f W (fine, %d iterations) against %.2f W (coarse, then %d on the fine grid); rmse %.5f "
              "against %.5f K\n", fine.fit.values[w], fine.fit.iterations, staged.fit.values[w], staged.fit.iterations,
              fine.fit.rmse_k, staged.fit.rmse_k);
  ASSERT_TRUE(fine.fit.converged);
  EXPECT_TRUE(staged.fit.converged);
  EXPECT_NEAR(staged.fit.rmse_k, fine.fit.rmse_k, 1e-4);
  // Within a tenth of the fit's own standard error of the same optimum.
  EXPECT_NEAR(staged.fit.values[w], fine.fit.values[w], 0.1 * fine.fit.std_error[w]);
}

TEST(CoarseRefit, WithoutAReadingOnTheCoarseGridTheFineRefitRunsAlone) {
  auto g = testing::generate({}, 3, 10, 12, 6);
  // Every reading the coarse grid would keep (each 1 s instant) masked: none left there.
  for (data::Cycle& c : g->dataset.cycles)
    for (data::Channel ch : {data::Channel::stator_winding_c, data::Channel::rotor_c}) {
      std::vector<float>& v = c.samples[data::index_of(ch)];
      for (std::size_t k = 0; k < v.size(); k += kCoarse) v[k] = std::nanf("");
    }
  const int windage = effect_index("windage");
  MotorFile with = g->motor;
  enable_effect(with, windage);
  LmSettings lm;
  lm.threads = 2;
  lm.max_iterations = 5;
  const data::Dataset coarse = internal::coarse_dataset(g->dataset, kCoarse);
  const auto fine = internal::refit_with(with, windage, g->calibrated.values, g->dataset, g->split.train, lm, {});
  internal::Refit staged;
  ASSERT_NO_THROW(staged = internal::refit_with(with, windage, g->calibrated.values, g->dataset, g->split.train, lm, {},
                                                &coarse));
  EXPECT_EQ(staged.fit.values, fine.fit.values);
  EXPECT_EQ(staged.fit.iterations, fine.fit.iterations);
}

}  // namespace
}  // namespace lptn::diagnose
