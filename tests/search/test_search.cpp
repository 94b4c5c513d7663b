// The search baselines on generated data: within their budget both leave the guess far behind,
// CMA-ES gets close to Levenberg-Marquardt's fit, and each stops at its budget.
#include <gtest/gtest.h>

#include <cstdio>

#include "lptn_testing/fleet_dump.hpp"
#include "trainer/lm/lm.hpp"
#include "trainer/search/search.hpp"

namespace lptn::search {
namespace {

const testing::Dump& generated() {
  static const testing::Dump* f = [] {
    auto* d = new testing::Dump;
    testing::generate_dump(*d, 4, 11, 1200, 1500, 0.25);
    return d;
  }();
  return *f;
}

double pooled(const calibrate::SplitMetrics& m) { return pool({m.stator, m.rotor}).rmse_k; }

TEST(Search, BothMethodsBeatTheGuessAndCmaEsComesCloseToLm) {
  const testing::Dump& f = generated();
  const Model<double> model = f.motor.model();
  const double guess = pooled(calibrate::evaluate_split(model, f.motor.initial_values(), f.dataset, f.split.test));
  const lm::LmReport lm = lm::fit_lm(f.motor, f.motor.initial_values(), f.dataset, f.split.train, lm::LmSettings{});
  const double lm_test = pooled(calibrate::evaluate_split(model, lm.values, f.dataset, f.split.test));
  SearchSettings s;
  s.budget_steps = 40'000'000;
  for (SearchMethod m : {SearchMethod::random, SearchMethod::cma_es}) {
    const SearchOutcome o = search_calibration(m, f.motor, f.dataset, f.split.train, s);
    const double test = pooled(calibrate::evaluate_split(model, o.values, f.dataset, f.split.test));
    std::printf("%s: test %.3f K (guess %.3f K, LM %.3f K), %zu sets, %.2e steps, %.1f s\n", to_string(m), test, guess, lm_test,
                o.evaluations, double(o.simulated_steps), o.seconds);
    EXPECT_LT(test, 0.5 * guess) << to_string(m);
    EXPECT_GE(o.simulated_steps, s.budget_steps);
    EXPECT_LT(o.simulated_steps, s.budget_steps + s.budget_steps / 10) << "stops at its budget";
    EXPECT_NEAR(o.best_train_rmse_k, pooled(calibrate::evaluate_split(model, o.values, f.dataset, f.split.train)), 1e-9);
    if (m == SearchMethod::cma_es) {
      EXPECT_LT(test, 1.1 * lm_test);
    }
  }
}

}  // namespace
}  // namespace lptn::search
