// The residual's shape (trainer/diagnose/internal/where.hpp, adequacy.hpp's shape_in_words) on
// residuals whose shape is known by construction: white noise, an exponentially correlated
// residual of a given correlation time, one that follows the sensor's own warming (a missing heat
// store), one that follows an input. Each must be measured and worded as what it is.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "trainer/diagnose/adequacy.hpp"
#include "trainer/diagnose/internal/where.hpp"

namespace lptn::diagnose {
namespace {

using data::Channel;

// A 90-minute cycle on the 10 Hz grid, the stator read at 1 Hz: it warms and cools twice (a
// 20-minute period) with the current, at 25 C ambient.
data::Cycle cycle(std::uint64_t seed) {
  data::Cycle c;
  c.name = "synthetic";
  c.dt_s = 0.1;
  c.steps = 54000;
  auto& stator = c.samples[static_cast<std::size_t>(Channel::stator_winding_c)];
  auto& ambient = c.samples[static_cast<std::size_t>(Channel::ambient_c)];
  auto& current = c.samples[static_cast<std::size_t>(Channel::current_a)];
  stator.assign(c.steps, NAN);
  ambient.assign(c.steps, 25.0f);
  current.assign(c.steps, 0.0f);
  std::mt19937_64 rng(seed);
  // The current switches every 10 min, at random levels.
  std::uniform_real_distribution<double> level(0, 400);
  double amps = level(rng), temp = 40;
  for (std::size_t k = 0; k < c.steps; ++k) {
    if (k % 6000 == 0) amps = level(rng);
    temp += 0.1 * ((25 + amps * amps / 2000) - temp) / 400;  // a 400 s node
    current[k] = static_cast<float>(amps);
    if (k % 10 == 0) stator[k] = static_cast<float>(temp);
  }
  return c;
}

// `residual(k, cycle)` at the stator's readings (every `read_every` grid steps: 10 is 1 Hz); the
// sums over four cycles, then the sensor's verdict as assess_adequacy would make it (inadequate, so
// that it is worded).
template <class Residual>
SensorAdequacy shaped(Residual residual, std::size_t read_every = 10) {
  internal::WhereSums sums;
  std::vector<std::size_t> all{0};
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    data::Dataset d;
    d.cycles.push_back(cycle(seed));
    data::Cycle& c = d.cycles[0];
    auto& stator = c.samples[static_cast<std::size_t>(Channel::stator_winding_c)];
    for (std::size_t k = 0; k < c.steps; ++k)
      if (k % read_every != 0) stator[k] = NAN;
    const internal::RegionEdges edges = internal::region_edges(d, all);
    std::vector<float> r(c.steps, NAN);
    std::mt19937_64 rng(100 + seed);
    for (std::size_t k = 0; k < c.steps; ++k)
      if (!std::isnan(c.at(Channel::stator_winding_c, k))) r[k] = static_cast<float>(residual(c, k, rng));
    sums += internal::where_sums(c, Channel::stator_winding_c, r, edges);
  }
  SensorAdequacy s;
  s.sensor = "stator";
  s.adequate = false;
  s.where = internal::where(sums, internal::RegionEdges{});
  s.shape = internal::shape(sums);
  return s;
}

TEST(ResidualShape, WhiteNoiseIsFasterThanAnyNode) {
  const SensorAdequacy s = shaped([](const data::Cycle&, std::size_t, std::mt19937_64& rng) {
    return std::normal_distribution<double>(0, 0.4)(rng);
  });
  std::printf("white noise: %s\n", shape_in_words(s).c_str());
  EXPECT_LT(s.shape.correlation_time_s, 2.0);
  EXPECT_NEAR(s.shape.mean_k, 0, 0.02);
  EXPECT_NE(shape_in_words(s).find("faster than any node"), std::string::npos);
}

// An AR(1) residual sampled at 1 Hz whose autocorrelation is exp(-lag / tau): the measured
// correlation time is tau, within the scatter of four 90-minute cycles; it follows nothing.
TEST(ResidualShape, AnExponentiallyCorrelatedResidualHasItsCorrelationTime) {
  for (const double tau : {30.0, 300.0, 1200.0}) {
    double state = 0;
    const double a = std::exp(-1.0 / tau);
    const SensorAdequacy s = shaped([&](const data::Cycle&, std::size_t k, std::mt19937_64& rng) {
      const double e = std::normal_distribution<double>(0, std::sqrt(1 - a * a))(rng);
      state = k == 0 ? e / std::sqrt(1 - a * a) : a * state + e;
      return state;
    });
    std::printf("tau %.0f s: correlation time %.0f s; %s\n", tau, s.shape.correlation_time_s, shape_in_words(s).c_str());
    EXPECT_NEAR(s.shape.correlation_time_s, tau, 0.3 * tau) << tau;
    EXPECT_FALSE(s.shape.correlation_time_at_least);
    // Independent of every input and of the warming: a chance correlation on few independent
    // samples (a 20-minute residual over six hours) is not worded as a cause.
    const std::string words = shape_in_words(s);
    if (tau >= kFastResidualS) {
      EXPECT_NE(words.find("follows it beyond chance"), std::string::npos) << words;
    }
  }
}

// A sensor read every 10 s: no pairs of residuals at the lags shorter than that, and the correlation
// time still measured from the lags that have them.
TEST(ResidualShape, ASensorReadEveryTenSecondsHasItsCorrelationTime) {
  double state = 0;
  const double tau = 300, a = std::exp(-10.0 / tau);  // one step per reading
  const SensorAdequacy s = shaped([&](const data::Cycle&, std::size_t k, std::mt19937_64& rng) {
    const double e = std::normal_distribution<double>(0, std::sqrt(1 - a * a))(rng);
    state = k == 0 ? e / std::sqrt(1 - a * a) : a * state + e;
    return state;
  }, 100);
  std::printf("read every 10 s, tau %.0f s: correlation time %.0f s\n", tau, s.shape.correlation_time_s);
  EXPECT_NEAR(s.shape.correlation_time_s, tau, 0.3 * tau);
  EXPECT_NE(shape_in_words(s), "");
}

// The model warms and cools faster than the sensor's node: model - measured is the measured
// warming rate times a lag (a mass the model lacks), plus the sensor's noise.
TEST(ResidualShape, AResidualThatFollowsTheWarmingIsAMissingHeatStore) {
  const SensorAdequacy s = shaped([](const data::Cycle& c, std::size_t k, std::mt19937_64& rng) {
    const std::size_t back = k >= 600 ? k - 600 : 0;  // 60 s
    const double rate = (c.at(Channel::stator_winding_c, k) - c.at(Channel::stator_winding_c, back)) / 60.0;
    return 20.0 * rate + std::normal_distribution<double>(0, 0.2)(rng);
  });
  const std::string words = shape_in_words(s);
  std::printf("follows the warming: %s\n", words.c_str());
  EXPECT_GT(s.shape.with_warming, 0.5);
  EXPECT_GE(s.shape.correlation_time_s, kFastResidualS);
  EXPECT_NE(words.find("warms and cools faster than the motor"), std::string::npos) << words;
  EXPECT_NE(words.find("mass_"), std::string::npos) << words;
}

// A heat source the model lacks, growing with the current: the model runs too cold after high
// current (the residual is minus the current through a 10-minute lag, as a node would filter it).
TEST(ResidualShape, AResidualThatFollowsAnInputNamesTheInput) {
  double lagged = 0;
  const SensorAdequacy s = shaped([&](const data::Cycle& c, std::size_t k, std::mt19937_64& rng) {
    const double amps = c.at(Channel::current_a, k);
    lagged = k == 0 ? amps : lagged + (amps - lagged) * 1.0 / 600;  // per reading (1 s)
    return -lagged / 100 + std::normal_distribution<double>(0, 0.2)(rng);
  });
  const std::string words = shape_in_words(s);
  std::printf("follows the current: %s\n", words.c_str());
  ASSERT_FALSE(s.where.follows.empty());
  EXPECT_EQ(s.where.follows.front().input, "current");
  EXPECT_NE(words.find("heat that grows with current is missing"), std::string::npos) << words;
}

TEST(ResidualShape, AnAdequateSensorIsNotWorded) {
  SensorAdequacy s = shaped([](const data::Cycle&, std::size_t, std::mt19937_64& rng) {
    return std::normal_distribution<double>(0, 0.4)(rng);
  });
  s.adequate = true;
  EXPECT_EQ(shape_in_words(s), "");
}

}  // namespace
}  // namespace lptn::diagnose
