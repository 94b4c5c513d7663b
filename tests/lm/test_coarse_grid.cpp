// The coarse grid TD3's sequential formulation trains on (data::coarse_grid) and the scorer it
// trains with (SetScorer): the coarse grid must not move the fit, and the scorer must score a set
// exactly as the metrics do.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <algorithm>

#include "lptn_testing/fleet_dump.hpp"
#include "trainer/lm/lm.hpp"
#include "trainer/calibrate/set_scorer.hpp"
#include "trainer/data/coarse_grid.hpp"

namespace lptn::lm {
namespace {

struct Fixture : testing::Dump {
  data::Dataset coarse;
  lm::LmReport fine_fit;
};

const Fixture& generated() {
  static const Fixture* f = [] {
    auto* fx = new Fixture;
    testing::generate_dump(*fx, 6, 3, 1800, 2400, 1.0 / 3.0);
    for (const data::Cycle& c : fx->dataset.cycles) fx->coarse.cycles.push_back(data::coarse_grid(c, 10));
    fx->fine_fit = lm::fit_lm(fx->motor, fx->motor.initial_values(), fx->dataset, fx->split.train, lm::LmSettings{});
    return fx;
  }();
  return *f;
}

double pooled(const calibrate::SplitMetrics& m) { return model::pool({m.stator, m.rotor}).rmse_k; }

TEST(CoarseGrid, AveragesInputsKeepsTheCurrentsRmsAndSamplesTheSensors) {
  data::Cycle c;
  c.steps = 25;
  c.dt_s = 0.1;
  for (data::Channel ch : data::kAllChannels) c.samples[data::index_of(ch)].resize(c.steps);
  for (std::size_t k = 0; k < c.steps; ++k) {
    c.samples[data::index_of(data::Channel::speed_rpm)][k] = static_cast<float>(k);
    c.samples[data::index_of(data::Channel::current_a)][k] = k % 2 ? 3.0f : 4.0f;
    c.samples[data::index_of(data::Channel::stator_winding_c)][k] = static_cast<float>(100 + k);
    c.samples[data::index_of(data::Channel::torque_nm)][k] = k < 12 ? std::nanf("") : 1.0f;
  }
  const data::Cycle g = data::coarse_grid(c, 10);
  ASSERT_EQ(g.steps, 3u);  // t = 0, 1, 2 s
  EXPECT_DOUBLE_EQ(g.dt_s, 1.0);
  EXPECT_FLOAT_EQ(g.at(data::Channel::speed_rpm, 0), 4.5f);
  EXPECT_FLOAT_EQ(g.at(data::Channel::speed_rpm, 2), 22.0f);  // the last step averages what exists: 20..24
  EXPECT_FLOAT_EQ(g.at(data::Channel::current_a, 0), static_cast<float>(std::sqrt(12.5)));
  EXPECT_FLOAT_EQ(g.at(data::Channel::stator_winding_c, 1), 110.0f);
  EXPECT_TRUE(std::isnan(g.at(data::Channel::torque_nm, 0)));
  EXPECT_FLOAT_EQ(g.at(data::Channel::torque_nm, 1), 1.0f);
  const data::Cycle same = data::coarse_grid(c, 1);  // bit for bit (NaN included)
  EXPECT_EQ(same.steps, c.steps);
  for (std::size_t i = 0; i < data::kNumChannels; ++i)
    EXPECT_EQ(std::memcmp(same.samples[i].data(), c.samples[i].data(), c.steps * sizeof(float)), 0) << i;
  EXPECT_THROW(data::coarse_grid(c, 0), std::invalid_argument);
}

// The gate for training on a coarse grid: the error at LM's optimum moves by less than
// 0.02 K, both as the coarse grid scores the fine optimum and as the fine grid scores the
// coarse grid's own optimum.
TEST(CoarseGrid, OneSecondGridMovesTheErrorAtLmsOptimumByLessThanTwoHundredthsOfAKelvin) {
  const Fixture& f = generated();
  const Model<double> model = f.motor.model();
  const ParamVector<double>& best = f.fine_fit.values;
  const double fine_train = pooled(calibrate::evaluate_split(model, best, f.dataset, f.split.train));
  const double coarse_train = pooled(calibrate::evaluate_split(model, best, f.coarse, f.split.train));
  const lm::LmReport coarse_fit = lm::fit_lm(f.motor, f.motor.initial_values(), f.coarse, f.split.train, lm::LmSettings{});
  const double fine_test = pooled(calibrate::evaluate_split(model, best, f.dataset, f.split.test));
  const double coarse_fit_test = pooled(calibrate::evaluate_split(model, coarse_fit.values, f.dataset, f.split.test));
  const double coarse_fit_train = pooled(calibrate::evaluate_split(model, coarse_fit.values, f.dataset, f.split.train));
  std::printf("LM's optimum: train %.4f K on 0.1 s, %.4f K on 1 s; the 1 s fit on 0.1 s: train %.4f K, test %.4f K (0.1 s fit %.4f K)\n",
              fine_train, coarse_train, coarse_fit_train, coarse_fit_test, fine_test);
  EXPECT_LT(std::abs(coarse_train - fine_train), 0.02);
  EXPECT_LT(std::abs(coarse_fit_test - fine_test), 0.02);
  EXPECT_LT(std::abs(coarse_fit_train - fine_train), 0.02);
}

std::vector<double> normalized(const calibrate::FreeParameters& free, const ParamVector<double>& p) {
  std::vector<double> u;
  for (std::size_t j = 0; j < free.size(); ++j) u.push_back(to_normalized(p[free.index[j]], free.min[j], free.max[j]));
  return u;
}

std::vector<data::Cycle> train_cycles(const data::Dataset& d, const calibrate::Split& s) {
  std::vector<data::Cycle> out;
  for (std::size_t c : s.train) out.push_back(d.cycles[c]);
  return out;
}

TEST(SetScorer, ScoresASetAsTheMetricsDoOnAnyNumberOfThreads) {
  const Fixture& f = generated();
  const Model<double> model = f.motor.model();
  const calibrate::FreeParameters free = calibrate::FreeParameters::from_motor(f.motor);
  const calibrate::SetScorer scorer(model, free, f.motor.initial_values(), train_cycles(f.dataset, f.split));
  std::vector<double> u = normalized(free, f.fine_fit.values);
  const std::vector<double> guess = normalized(free, f.motor.initial_values());
  u.insert(u.end(), guess.begin(), guess.end());
  calibrate::SetScore one[2], two[2];
  scorer.score(u.data(), 2, one, 1);
  scorer.score(u.data(), 2, two, 2);
  const ParamVector<double> sets[2] = {scorer.params_for(u.data()), scorer.params_for(u.data() + free.size())};
  for (int i = 0; i < 2; ++i) {
    const calibrate::SplitMetrics m = calibrate::evaluate_split(model, sets[i], f.dataset, f.split.train);
    EXPECT_NEAR(one[i].rmse_k, pooled(m), 1e-6 * pooled(m)) << i;
    EXPECT_NEAR(one[i].stator_rmse_k, m.stator.rmse_k, 1e-6 * m.stator.rmse_k) << i;
    EXPECT_NEAR(one[i].rotor_rmse_k, m.rotor.rmse_k, 1e-6 * m.rotor.rmse_k) << i;
    EXPECT_EQ(one[i].features, two[i].features) << i;
    EXPECT_EQ(one[i].rmse_k, two[i].rmse_k) << i;
    EXPECT_GT(one[i].simulated_steps, 0u);
  }
  EXPECT_GT(one[1].rmse_k, 5 * one[0].rmse_k);  // the guess is far off
}

// Sets scored side by side (four at a time in vector registers, two for a remainder of two) get the
// very bits each gets scored alone (one set: the double run): six sets, a group of four and one
// of two, against each alone, on one thread and on two.
TEST(SetScorer, ScoresSetsSideBySideAsEachAloneToTheBit) {
  const Fixture& f = generated();
  const Model<double> model = f.motor.model();
  const calibrate::FreeParameters free = calibrate::FreeParameters::from_motor(f.motor);
  const calibrate::SetScorer scorer(model, free, f.motor.initial_values(), train_cycles(f.dataset, f.split));
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> d(-0.4, 0.4);
  const std::vector<double> fit = normalized(free, f.fine_fit.values);
  constexpr std::size_t kSets = 6;
  std::vector<double> u;
  for (std::size_t i = 0; i < kSets; ++i)
    for (std::size_t j = 0; j < free.size(); ++j) u.push_back(std::clamp(fit[j] + (i == 0 ? 0.0 : d(rng)), -1.0, 1.0));
  for (const int threads : {1, 2}) {
    calibrate::SetScore together[kSets];
    scorer.score(u.data(), kSets, together, threads);
    for (std::size_t i = 0; i < kSets; ++i) {
      calibrate::SetScore alone;
      scorer.score(u.data() + i * free.size(), 1, &alone, 1);
      EXPECT_EQ(std::memcmp(&together[i].rmse_k, &alone.rmse_k, sizeof(double)), 0) << i << " " << alone.rmse_k;
      EXPECT_EQ(std::memcmp(&together[i].stator_rmse_k, &alone.stator_rmse_k, sizeof(double)), 0) << i;
      EXPECT_EQ(std::memcmp(&together[i].rotor_rmse_k, &alone.rotor_rmse_k, sizeof(double)), 0) << i;
      EXPECT_EQ(together[i].features, alone.features) << i;
      EXPECT_EQ(together[i].simulated_steps, alone.simulated_steps) << i;
    }
    EXPECT_GT(together[kSets - 1].rmse_k, together[0].rmse_k);  // the sets differ: a moved set scores worse than the fit
  }
}

// The features say where the model is off: a stator winding that loses more heat to the air
// than the plant's reads cold, and colder the more air flows.
TEST(SetScorer, FeaturesPointAtTheConductanceThatIsOff) {
  const Fixture& f = generated();
  const Model<double> model = f.motor.model();
  const calibrate::FreeParameters free = calibrate::FreeParameters::from_motor(f.motor);
  const calibrate::SetScorer scorer(model, free, f.motor.initial_values(), train_cycles(f.dataset, f.split));
  ParamVector<double> p = f.fine_fit.values;
  calibrate::SetScore at_fit, off;
  std::vector<double> u = normalized(free, p);
  scorer.score(u.data(), 1, &at_fit, 1);
  p[kLambda1s] *= 1.3;
  u = normalized(free, p);
  scorer.score(u.data(), 1, &off, 1);
  const std::size_t bias = 1, high_airflow = 2;  // stator's: ln RMSE, bias, then the splits in kResidualSplits' order
  ASSERT_EQ(calibrate::kResidualSplits[0], "high_airflow");
  std::printf("stator bias feature %.3f -> %.3f, high-airflow split %.3f -> %.3f\n", at_fit.features[bias], off.features[bias],
              at_fit.features[high_airflow], off.features[high_airflow]);
  EXPECT_LT(std::abs(at_fit.features[bias]), 0.5);
  EXPECT_LT(off.features[bias], -1.0);
  EXPECT_LT(off.features[high_airflow], at_fit.features[high_airflow]);
  EXPECT_GT(off.rmse_k, at_fit.rmse_k);
}

}  // namespace
}  // namespace lptn::lm
