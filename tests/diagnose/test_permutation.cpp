// The permutation test's p-value: the orderings of its definition (drawn one after another from
// one seed), whatever the threads that compute their statistics.
#include <gtest/gtest.h>

#include <cstddef>
#include <random>
#include <vector>

#include "trainer/diagnose/internal/permutation.hpp"

namespace lptn::diagnose::internal {
namespace {

// A statistic that depends on the order: the series' covariance with its index.
double trend(const std::vector<double>& y) {
  double s = 0;
  for (std::size_t i = 0; i < y.size(); ++i) s += (static_cast<double>(i) - 0.5 * static_cast<double>(y.size() - 1)) * y[i];
  return s;
}

// The definition, one ordering at a time.
double serial_p_value(std::vector<double> items, double observed) {
  std::mt19937_64 rng(kOrderingSeed);
  int reached = 1;
  for (int i = 0; i < kOrderings; ++i) {
    std::shuffle(items.begin(), items.end(), rng);
    reached += trend(items) >= observed * (1 - 1e-12);
  }
  return static_cast<double>(reached) / (kOrderings + 1);
}

TEST(PermutationTest, IsTheDefinitionsCountOnAnyNumberOfThreads) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  // A weak trend, so that the p-value is neither 1/4001 nor near 1: every ordering's count matters.
  std::vector<double> y(40);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = 0.02 * static_cast<double>(i) + noise(rng);
  const double observed = trend(y);
  const double expected = serial_p_value(y, observed);
  ASSERT_GT(expected, 0.01);
  ASSERT_LT(expected, 0.99);
  for (const int threads : {1, 2, 3, 7})
    EXPECT_EQ(p_value(y, observed, trend, threads), expected) << "threads " << threads;
}

}  // namespace
}  // namespace lptn::diagnose::internal
