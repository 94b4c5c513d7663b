// The correlation time that inflates LM's standard errors and sets diagnose's effective residual
// count: the FFT's sums against the lag-by-lag definition, and AR(1) series whose answer is known.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "trainer/lm/correlation_time.hpp"

namespace lptn::lm {
namespace {

using Series = std::vector<std::vector<double>>;

// The definition, lag by lag (what lm.cpp computed before the FFT).
double by_definition(const Series& series) {
  double var = 0, count = 0;
  for (const auto& r : series)
    for (double e : r) var += e * e, count += 1;
  var /= count;
  double tau = 1;
  for (std::size_t lag = 1; lag < lm::kMaxCorrelationLag; ++lag) {
    double c = 0, n = 0;
    for (const auto& r : series)
      for (std::size_t k = lag; k < r.size(); ++k) c += r[k] * r[k - lag], n += 1;
    if (n < 100) break;
    const double rho = c / n / var;
    if (rho <= 0) break;
    tau += 2 * rho;
  }
  return tau;
}

// Cycles of AR(1) noise, x_k = phi x_{k-1} + e_k, demeaned, of the given lengths.
Series ar1(double phi, const std::vector<std::size_t>& lengths, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> e(0, 1);
  Series out;
  for (std::size_t n : lengths) {
    std::vector<double> r(n);
    double x = 0, mean = 0;
    for (double& v : r) mean += (v = x = phi * x + e(rng));
    mean /= static_cast<double>(n);
    for (double& v : r) v -= mean;
    out.push_back(std::move(r));
  }
  return out;
}

TEST(CorrelationTime, EqualsTheLagByLagSumOnCyclesOfUnequalLength) {
  for (const double phi : {0.0, 0.5, 0.9, 0.995}) {
    const Series s = ar1(phi, {20000, 7001, 13000, 150}, 3);
    const double fast = lm::correlation_time(s), slow = by_definition(s);
    EXPECT_NEAR(fast, slow, 1e-9 * slow) << "phi " << phi;
  }
}

TEST(CorrelationTime, SumsAreTheSameBitsOnAnyNumberOfThreads) {
  // The series' transforms run in parallel and are added in the series' order: a fit's correlation
  // time (and so its parameters' errors) does not depend on the machine's cores. Five series, one
  // too short to count, over 1, 2, 3 and 8 threads (more threads than series included).
  const Series s = ar1(0.9, {20000, 7001, 1, 13000, 150}, 5);
  const std::vector<double> one = lm::correlation_sums(s, 1);
  for (const int threads : {2, 3, 8}) {
    const std::vector<double> many = lm::correlation_sums(s, threads);
    ASSERT_EQ(many.size(), one.size());
    for (std::size_t i = 0; i < one.size(); ++i) ASSERT_EQ(many[i], one[i]) << "threads " << threads << ", entry " << i;
  }
  EXPECT_NEAR(lm::correlation_time_of_sums(one), by_definition(s), 1e-9 * by_definition(s));
}

TEST(CorrelationTime, IsOnePlusPhiOverOneMinusPhiForAr1Noise) {
  // Summed while positive, the estimate stops early on the noisy tail: within 10 % of the truth.
  for (const double phi : {0.5, 0.9, 0.98}) {
    const double truth = (1 + phi) / (1 - phi);
    EXPECT_NEAR(lm::correlation_time(ar1(phi, {200000, 200000}, 7)), truth, 0.1 * truth) << "phi " << phi;
  }
  EXPECT_NEAR(lm::correlation_time(ar1(0.0, {100000}, 9)), 1.0, 0.05);
}

TEST(CorrelationTime, StopsAtTheFirstLagThatIsNotPositive) {
  std::vector<double> alternating(1000);
  for (std::size_t k = 0; k < alternating.size(); ++k) alternating[k] = k % 2 ? 1.0 : -1.0;
  EXPECT_DOUBLE_EQ(lm::correlation_time({alternating}), 1.0);
  EXPECT_DOUBLE_EQ(lm::correlation_time({}), 1.0);
  EXPECT_DOUBLE_EQ(lm::correlation_time({std::vector<double>(500, 0.0)}), 1.0);
}

}  // namespace
}  // namespace lptn::lm
