// Parameter sets stepped side by side (lptn/lanes.hpp: run_cycle_lanes, the initial offsets'
// lanes): each lane must be the double run of its own set to the bit, through every effect of the
// library (their pow, exp and clamps per lane), and where the lanes' stage matrices would pivot on
// different rows (then the step is taken lane by lane).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "lptn/internal/small_lu.hpp"
#include "lptn/lanes.hpp"
#include "lptn_testing/reference_case.hpp"
#include "trainer/model/initial_offsets.hpp"
#include "trainer/model/simulate.hpp"

namespace lptn::model {
namespace {

const EffectSet kAll = (EffectSet{1} << kNumEffects) - 1;

// A cycle of `steps` grid steps of dt: load steps, coasting, the blower's levels, torque and
// voltage on the bus part of the time, a rotor reading or not.
data::Cycle make_cycle(std::size_t steps, double dt, bool rotor_measured, std::uint64_t seed) {
  using data::Channel;
  data::Cycle c;
  c.name = "lanes";
  c.steps = steps;
  c.dt_s = dt;
  for (Channel ch : data::kAllChannels) c.samples[data::index_of(ch)].assign(steps, std::nanf(""));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.3);
  auto set = [&](Channel ch, std::size_t k, double v) { c.samples[data::index_of(ch)][k] = static_cast<float>(v); };
  for (std::size_t k = 0; k < steps; ++k) {
    const double t = static_cast<double>(k) * dt;
    const double load = std::fmod(t, 900.0) < 500.0 ? 1.0 + 0.3 * std::sin(t / 97.0) : 0.0;
    const double speed = 600.0 + 1500.0 * (0.5 + 0.5 * std::sin(t / 611.0));
    set(Channel::speed_rpm, k, speed);
    set(Channel::current_a, k, 110.0 * load + 2.0);
    set(Channel::frequency_hz, k, speed / 30.0 + (load > 0 ? 1.2 : 0.0));
    set(Channel::airflow_m3s, k, std::fmod(t, 1700.0) < 800.0 ? 1.0 : 0.45);
    set(Channel::ambient_c, k, 18.0 + 4.0 * std::sin(t / 3000.0));
    if (std::fmod(t, 2400.0) < 1600.0) {
      set(Channel::torque_nm, k, 1500.0 * load);
      set(Channel::voltage_v, k, 1800.0 * speed / 2100.0);
    }
    set(Channel::stator_winding_c, k, 40.0 + 30.0 * (1.0 - std::exp(-t / 1500.0)) + noise(rng));
    if (rotor_measured) set(Channel::rotor_c, k, 35.0 + 40.0 * (1.0 - std::exp(-t / 2500.0)) + noise(rng));
  }
  return c;
}

// Four sets: the defaults, every parameter moved at random by up to 30 %, and one whose stator
// sensor lags by half a second, which on a 5 s grid makes its stage matrix pivot on another row
// than the others' (the sensor's row, gamma h / tau, outweighs the winding's in the winding's
// column); on a 1 s grid all four pivot alike.
std::vector<ParamVector<double>> four_sets() {
  std::vector<ParamVector<double>> sets(4, default_params<double>());
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> factor(0.7, 1.3);
  for (int s = 1; s < 4; ++s)
    for (int i = 0; i < kNumParams; ++i) {
      const ParamSpec& spec = param_spec(i);
      sets[s][i] = std::clamp(sets[s][i] * factor(rng), spec.min, spec.max);
      if (sets[s][i] == 0.0) sets[s][i] = 0.01 * factor(rng) * spec.max;  // a neutral 0: switch it on a little
    }
  sets[3][param_index("sensor_time_constant_s")] = 0.5;
  return sets;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(Lanes, TheLanePivotIsEachLanesOwnOrNone) {
  internal::SmallLu<Lanes<2>> lu;
  // Column 0: lane 0's largest entry is on the diagonal, lane 1's below it.
  const double m[2][2][2] = {{{4, 1}, {1, 3}}, {{1, 1}, {4, 3}}};
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int l = 0; l < 2; ++l) lu.lu[i][j].set_lane(l, m[l][i][j]);
  EXPECT_FALSE(lu.factor_in_place(2));  // the lanes would exchange different rows
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int l = 0; l < 2; ++l) lu.lu[i][j].set_lane(l, m[0][i][j] * (1 + l));
  ASSERT_TRUE(lu.factor_in_place(2));  // both pivot on the diagonal: as one double each
  internal::SmallLu<double> one;
  for (int l = 0; l < 2; ++l) {
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) one.lu[i][j] = m[0][i][j] * (1 + l);
    ASSERT_TRUE(one.factor_in_place(2));
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) EXPECT_TRUE(same_bits(lu.lu[i][j].lane(l), one.lu[i][j])) << l << i << j;
  }
}

TEST(Lanes, EachLaneRunsACycleAsTheDoubleRunOfItsSetDoesToTheBit) {
  const Model<double> model(testing::example_motor(), kAll);
  const std::vector<ParamVector<double>> sets = four_sets();
  Lanes<4> p[kNumParams];
  for (int l = 0; l < 4; ++l)
    for (int i = 0; i < kNumParams; ++i) p[i].set_lane(l, sets[l][i]);
  int together = 0, apart = 0;  // steps the lanes can take as one, and steps they must take apart
  for (const auto& [dt, rotor] : {std::pair{1.0, true}, std::pair{5.0, false}}) {
    const data::Cycle cycle = make_cycle(dt == 1.0 ? 4000 : 1000, dt, rotor, rotor ? 1 : 2);
    const PreparedCycle prepared = prepare_cycle(model, cycle);
    InitialOffsets<double> offsets[4];
    estimate_initial_offsets_lanes<4>(model, sets.data(), cycle, offsets, kInitialOffsetWindowS, &prepared);
    std::vector<std::vector<double>> lane_states(4);
    run_cycle_lanes<4>(model, sets.data(), cycle, [&](std::ptrdiff_t, const Lanes<4>* x) {
      for (int l = 0; l < 4; ++l)
        for (int i = 0; i < model.num_states(); ++i) lane_states[l].push_back(x[i].lane(l));
    }, offsets, &prepared);
    for (int l = 0; l < 4; ++l) {
      const InitialOffsets<double> alone = estimate_initial_offsets(model, sets[l], cycle, kInitialOffsetWindowS, &prepared);
      EXPECT_TRUE(same_bits(offsets[l].stator_core, alone.stator_core)) << l;
      EXPECT_TRUE(same_bits(offsets[l].rotor_core, alone.rotor_core)) << l;
      std::vector<double> states;
      run_cycle(model, sets[l].data(), cycle, [&](std::ptrdiff_t, const double* x) {
        for (int i = 0; i < model.num_states(); ++i) states.push_back(x[i]);
      }, alone, SIZE_MAX, &prepared);
      ASSERT_EQ(states.size(), lane_states[l].size());
      std::size_t differing = 0;
      for (std::size_t k = 0; k < states.size(); ++k) differing += same_bits(states[k], lane_states[l][k]) ? 0 : 1;
      EXPECT_EQ(differing, 0u) << "lane " << l << ", dt " << dt << " s";
      EXPECT_GT(std::abs(states.back() - states[model.num_states() - 1]), 1.0);  // the run went somewhere
    }
    // Which way each step of this cycle went (the pivots depend on the inputs and parameters alone).
    Lanes<4> x[kMaxStates];
    initial_state_for(model, cycle, x);
    Model<double>::StepWorkspace<Lanes<4>> work;
    for (std::size_t k = 0; k + 1 < cycle.steps; ++k) {
      Lanes<4> trial[kMaxStates];
      std::copy(x, x + kMaxStates, trial);
      (model.step(trial, prepared[k], p, cycle.dt_s, work) ? together : apart) += 1;
    }
  }
  EXPECT_GT(together, 0);
  EXPECT_GT(apart, 0);
}

}  // namespace
}  // namespace lptn::model
