// The report's statistics on series whose answer is known.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "tools/report/stats.hpp"
#include "trainer/calibrate/sensor_noise.hpp"

namespace lptn::report {
namespace {

std::vector<double> white_noise(std::size_t n, unsigned seed) {
  std::mt19937 gen(seed);
  std::normal_distribution<double> d(0, 1);
  std::vector<double> v(n);
  for (double& x : v) x = d(gen);
  return v;
}

// A slow input, like a speed profile: AR(1) with coefficient 0.95.
std::vector<double> slow_input(std::size_t n, unsigned seed) {
  std::vector<double> v = white_noise(n, seed);
  for (std::size_t i = 1; i < n; ++i) v[i] += 0.95 * v[i - 1];
  return v;
}

TEST(ReportStats, AutocorrelationOfWhiteNoiseStaysWithinTheBand) {
  const Segments e{white_noise(3000, 1), white_noise(2000, 2)};
  const auto r = autocorrelation(e, 50);
  EXPECT_DOUBLE_EQ(r[0], 1.0);
  const double band = white_noise_band(valid_count(e));
  int outside = 0;
  for (std::size_t k = 1; k < r.size(); ++k) outside += std::abs(r[k]) > band;
  EXPECT_LE(outside, 5);  // 5 % of 50 lags expected outside by chance; allow a little more
}

TEST(ReportStats, ResidualDrivenByAnInputCrossCorrelatesBeyondTheBand) {
  const auto x = slow_input(5000, 3);
  auto e = white_noise(5000, 4);
  for (std::size_t t = 10; t < e.size(); ++t) e[t] += 0.3 * x[t - 10];  // the residual follows the input by 10 steps
  const Segments xs{x}, es{e};
  const std::size_t lag = 40;
  const auto r = cross_correlation(xs, es, lag);
  const double band = bartlett_band(valid_count(es), autocorrelation(xs, lag), autocorrelation(es, lag));
  EXPECT_GT(band, white_noise_band(5000));  // both series are autocorrelated: the band widens
  EXPECT_GT(r[lag + 10], band);
  std::size_t peak = 0;
  for (std::size_t i = 0; i < r.size(); ++i) peak = r[i] > r[peak] ? i : peak;
  EXPECT_NEAR(static_cast<double>(peak), static_cast<double>(lag + 10), 3);
}

TEST(ReportStats, UnrelatedSlowSeriesCrossTheCorrectedBandAboutOneTimeInTwenty) {
  // Uncorrected, two independent slow series would cross 1.96/sqrt(n) most of the time.
  int outside = 0, outside_uncorrected = 0;
  for (unsigned seed = 0; seed < 40; ++seed) {
    const Segments x{slow_input(5000, 100 + seed)}, e{slow_input(5000, 200 + seed)};
    const double r0 = cross_correlation(x, e, 0)[0];
    outside += std::abs(r0) > bartlett_band(5000, autocorrelation(x, 200), autocorrelation(e, 200));
    outside_uncorrected += std::abs(r0) > white_noise_band(5000);
  }
  EXPECT_LE(outside, 6);
  EXPECT_GE(outside_uncorrected, 15);
}

// A 1 Hz sensor on the 10 Hz grid, linearly interpolated between its readings, as the loader
// resamples it: readings at steps offset, offset + 10, ...; `drift` is added (the model's error).
std::vector<float> interpolated_sensor(std::size_t readings, std::size_t offset, double sigma, double drift_k,
                                       unsigned seed) {
  const auto noise = white_noise(readings, seed);
  std::vector<float> e(offset + 10 * (readings - 1) + 1, std::nanf(""));
  for (std::size_t j = 0; j + 1 < readings; ++j) {
    for (std::size_t f = 0; f <= 10; ++f) {
      const double w = static_cast<double>(f) / 10;
      e[offset + 10 * j + f] = static_cast<float>(sigma * ((1 - w) * noise[j] + w * noise[j + 1]));
    }
  }
  for (std::size_t k = 0; k < e.size(); ++k)
    e[k] += static_cast<float>(drift_k * std::sin(2 * std::numbers::pi * static_cast<double>(k) / 18000));
  return e;
}

// The noise under a slow error twenty times its size (the rotor's case), whatever the phase of the
// readings on the grid (the generator's stator reads at whole seconds, its rotor half a second
// later), and the noise alone where there is nothing else (the stator's).
TEST(ReportStats, SensorNoiseIsTheNoiseNotTheSlowErrorAtAnyPhase) {
  for (std::size_t offset : {0u, 5u, 9u}) {
    EXPECT_NEAR(calibrate::sensor_noise(interpolated_sensor(6000, offset, 0.4, 0, 7), 10).sigma(), 0.4, 0.02) << offset;
    EXPECT_NEAR(calibrate::sensor_noise(interpolated_sensor(6000, offset, 0.4, 8, 7), 10).sigma(), 0.4, 0.02) << offset;
  }
  // Pooled over cycles; every 0.1 s step a reading (period 1) is plain white noise.
  calibrate::NoiseSum pooled = calibrate::sensor_noise(interpolated_sensor(3000, 3, 0.5, 0, 8), 10);
  pooled += calibrate::sensor_noise(interpolated_sensor(3000, 6, 0.5, 0, 9), 10);
  EXPECT_NEAR(pooled.sigma(), 0.5, 0.03);
  std::vector<float> white;
  for (double v : white_noise(6000, 10)) white.push_back(static_cast<float>(0.3 * v));
  EXPECT_NEAR(calibrate::sensor_noise(white, 1).sigma(), 0.3, 0.015);
  EXPECT_TRUE(std::isnan(calibrate::sensor_noise(std::vector<float>(5, std::nanf("")), 1).sigma()));
}

TEST(ReportStats, RegionBinsCountEveryValidSampleOnce) {
  const auto x = white_noise(1000, 7), y = white_noise(1000, 8);
  auto e = white_noise(1000, 9);
  e[3] = std::nan("");
  const auto bins = bin_residuals(x, e, linear_edges(-1, 1, 4));  // values beyond +-1 land in the end bins
  std::size_t n = 0;
  for (const Bin& b : bins) n += b.n;
  EXPECT_EQ(n, 999u);
  std::size_t n2 = 0;
  for (const auto& row : bin_residuals_2d(x, y, e, linear_edges(-1, 1, 3), aligned_edges(-0.3, 0.4, 0.25))) {
    for (const Bin& b : row) n2 += b.n;
  }
  EXPECT_EQ(n2, 999u);
}

TEST(ReportStats, BinStatisticsAreMeanAndRmse) {
  const auto bins = bin_residuals({0.1, 0.2, 0.9}, {1, 3, -2}, {0, 0.5, 1});
  ASSERT_EQ(bins.size(), 2u);
  EXPECT_DOUBLE_EQ(bins[0].mean, 2);
  EXPECT_DOUBLE_EQ(bins[0].rmse, std::sqrt(5.0));
  EXPECT_EQ(bins[1].n, 1u);
  EXPECT_DOUBLE_EQ(bins[1].rmse, 2);
}

TEST(ReportStats, WorstWindowsAreSortedAndDoNotOverlap) {
  Segments e{white_noise(2000, 10), white_noise(1500, 11)};
  for (std::size_t t = 500; t < 600; ++t) e[0][t] *= 5;  // one bad stretch
  for (std::size_t t = 700; t < 800; ++t) e[1][t] *= 3;
  const auto w = worst_windows(e, 120, 10, 8);
  ASSERT_EQ(w.size(), 8u);
  EXPECT_EQ(w[0].segment, 0u);
  EXPECT_LE(w[0].start, 500u);
  EXPECT_GE(w[0].start + w[0].length, 600u);
  EXPECT_EQ(w[1].segment, 1u);
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (i > 0) {
      EXPECT_GE(w[i - 1].rmse, w[i].rmse);
    }
    for (std::size_t j = 0; j < i; ++j) {
      const bool overlap = w[i].segment == w[j].segment && w[i].start < w[j].start + w[j].length &&
                           w[j].start < w[i].start + w[i].length;
      EXPECT_FALSE(overlap) << i << " overlaps " << j;
    }
  }
}

TEST(ReportStats, EnvelopeKeepsEveryBucketsExtremes) {
  const std::vector<float> v{1, 5, 2, NAN, NAN, NAN, 3};
  const Envelope env = envelope(v, 3);
  ASSERT_EQ(env.mean.size(), 3u);
  EXPECT_DOUBLE_EQ(env.lo[0], 1);
  EXPECT_DOUBLE_EQ(env.hi[0], 5);
  EXPECT_TRUE(std::isnan(env.mean[1]));
  EXPECT_DOUBLE_EQ(env.mean[2], 3);
}

}  // namespace
}  // namespace lptn::report
