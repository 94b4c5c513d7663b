// The integrator against the exact solution of the same piecewise-constant system, and its
// stability for stiff and extreme parameter sets.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <unsupported/Eigen/MatrixFunctions>

#include "lptn/internal/small_lu.hpp"
#include "lptn/model.hpp"
#include "lptn_testing/reference_case.hpp"

namespace lptn {
namespace {

// Exact step of dx/dt = A x + c over h with A, c held: the matrix exponential of [[A c] [0 0]] h.
void exact_step(const HeatBalance<double>& sys, double* x, double h) {
  const int n = sys.n;
  Eigen::MatrixXd aug = Eigen::MatrixXd::Zero(n + 1, n + 1);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) aug(i, j) = sys.a[i][j] * h;
    aug(i, n) = sys.c[i] * h;
  }
  const Eigen::MatrixXd e = aug.exp();
  Eigen::VectorXd xv(n + 1);
  for (int i = 0; i < n; ++i) xv[i] = x[i];
  xv[n] = 1.0;
  const Eigen::VectorXd next = e * xv;
  for (int i = 0; i < n; ++i) x[i] = next[i];
}

// A reference case with everything moving: load steps and ramps, regenerative braking, standstill
// with pulses off, the blower changing, ambient drifting.
Inputs<double> reference_inputs(double t) {
  Inputs<double> in = testing::rated_inputs();
  const double phase = std::fmod(t, 600.0);
  in.speed_rpm = phase < 100 ? 25.0 * phase : (phase < 400 ? 2500.0 : (phase < 500 ? 2500.0 - 25.0 * (phase - 400) : 0.0));
  const bool standing = phase >= 500;
  in.torque_nm = phase < 100 ? 2300.0 : (phase < 400 ? 500.0 : (phase < 500 ? -1800.0 : 0.0));
  in.current_a = standing ? 0.0 : 40.0 + 0.045 * std::abs(in.torque_nm) * 1.2;
  in.frequency_hz = 2 * in.speed_rpm / 60 + (standing ? 0.0 : in.torque_nm * 0.00035);
  in.voltage_v = std::min(1900.0, 29.2 * in.frequency_hz);
  in.airflow_m3s = std::fmod(t, 1500.0) < 700 ? 1.0 : 0.45;
  in.ambient_c = 20 + 5 * std::sin(t / 2000.0);
  in.has_torque = false;
  return in;
}

TEST(Integrator, StaysWithinAHundredthOfAKelvinOfTheExactSolutionAtATenthOfASecond) {
  const auto m = testing::example_motor();
  const EffectSet all = (EffectSet{1} << kNumEffects) - 1;
  for (EffectSet effects : {EffectSet{0}, all}) {
    const Model<double> model(m, effects);
    auto p = default_params<double>();
    p[param_index("sensor_time_constant_s")] = 20.0;
    double x[kMaxStates], ref[kMaxStates];
    model.initial_state(x, 20.0, 20.0);
    model.initial_state(ref, 20.0, 20.0);
    double worst = 0, hottest = 0;
    for (int k = 0; k < 36000; ++k) {
      const Inputs<double> in = reference_inputs(0.1 * k);
      HeatBalance<double> sys;
      model.assemble(in, p.data(), sys);
      ASSERT_TRUE(Sdirk2<double>::step(sys, x, 0.1));
      exact_step(sys, ref, 0.1);
      for (int i = 0; i < model.num_states(); ++i) worst = std::max(worst, std::abs(x[i] - ref[i]));
      hottest = std::max(hottest, ref[0]);
    }
    EXPECT_LT(worst, 0.01) << "effects " << effects;
    // The case does exercise the model: the winding runs hot. With every effect on, the
    // dictionary's three thermal masses (at their start values, 100 W/K to 300 kJ/K each) take up
    // part of the heat: 79.6 °C where the paper's model reaches over 80.
    EXPECT_GT(hottest, effects == 0 ? 80.0 : 75.0);
  }
}

// Second order: halving the step cuts the error by about four.
TEST(Integrator, IsSecondOrder) {
  const auto m = testing::example_motor();
  const Model<double> model(m, 0);
  const auto p = default_params<double>();
  const Inputs<double> in = testing::rated_inputs();
  auto error_at = [&](double h) {
    double x[kMaxStates], ref[kMaxStates];
    model.initial_state(x, 20.0, 20.0);
    model.initial_state(ref, 20.0, 20.0);
    HeatBalance<double> sys;
    model.assemble(in, p.data(), sys);
    const int steps = static_cast<int>(std::lround(600.0 / h));
    for (int k = 0; k < steps; ++k) Sdirk2<double>::step(sys, x, h);
    exact_step(sys, ref, 600.0);
    return std::abs(x[0] - ref[0]);
  };
  const double e1 = error_at(2.0), e2 = error_at(1.0);
  EXPECT_GT(e1 / e2, 3.5);
  EXPECT_LT(e1 / e2, 4.5);
}

// Any positive parameter set, any step: a network without losses (pulses off) cannot gain energy.
// The C-weighted distance from the air temperature never grows, even as the airflow (and so the
// state matrix) jumps every step, for conductances at the extremes of their bounds.
TEST(Integrator, NeverAmplifiesAPassiveNetworkWhateverTheParametersAndStep) {
  const auto m = testing::example_motor();
  const Model<double> model(m, 0);
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> corner(0, 1);
  std::uniform_real_distribution<double> airflow(0.0, 2.0);
  for (int trial = 0; trial < 64; ++trial) {
    auto p = default_params<double>();
    for (int i : {kLambda1s, kLambda2s, kLambda12s, kLambda1r, kLambda2r, kLambda12r})
      p[i] = corner(rng) ? param_spec(i).max : param_spec(i).min;
    for (double h : {0.1, 10.0, 1000.0}) {
      double x[kMaxStates] = {180.0, 40.0, 220.0, 10.0};
      Inputs<double> in;
      in.ambient_c = 20.0;
      auto energy = [&] {
        double e = 0;
        for (int i = 0; i < 4; ++i) e += m.capacitance_j_per_k[i] * (x[i] - in.ambient_c) * (x[i] - in.ambient_c);
        return e;
      };
      double last = energy();
      for (int k = 0; k < 200; ++k) {
        in.airflow_m3s = airflow(rng);
        ASSERT_TRUE(model.step(x, in, p.data(), h));
        const double now = energy();
        ASSERT_TRUE(std::isfinite(now));
        // Relative round-off, plus an absolute floor 18 decades below the starting energy (~1e9).
        ASSERT_LE(now, last * (1 + 1e-12) + 1e-9) << "trial " << trial << " h " << h << " step " << k;
        last = now;
      }
    }
  }
}

// Stiff sets with losses and every effect on: a fast sensor, a very strong stator-core path and a
// tiny winding capacitance. Still within 0.05 K of the exact solution at 0.1 s, and a huge step
// lands on the steady state instead of ringing (L-stability). Huge against the slowest mode: the
// thermal masses' time constants are thousands of seconds, where SDIRK2's factor at 1e5 s is still
// -0.1 to -0.15 a step; at 1e8 s it is 1e-4.
TEST(Integrator, HandlesStiffParameterSets) {
  auto m = testing::example_motor();
  m.capacitance_j_per_k[kStatorWinding] = 2000.0;
  const EffectSet all = (EffectSet{1} << kNumEffects) - 1;
  const Model<double> model(m, all);
  auto p = default_params<double>();
  p[kLambda12s] = 5000.0;
  p[kLambda12r] = 5000.0;
  p[param_index("sensor_time_constant_s")] = 0.5;
  double x[kMaxStates], ref[kMaxStates];
  model.initial_state(x, 20.0, 20.0);
  model.initial_state(ref, 20.0, 20.0);
  double worst = 0;
  for (int k = 0; k < 18000; ++k) {
    HeatBalance<double> sys;
    model.assemble(reference_inputs(0.1 * k), p.data(), sys);
    Sdirk2<double>::step(sys, x, 0.1);
    exact_step(sys, ref, 0.1);
    for (int i = 0; i < model.num_states(); ++i) worst = std::max(worst, std::abs(x[i] - ref[i]));
  }
  EXPECT_LT(worst, 0.05);

  const Inputs<double> in = testing::rated_inputs();
  HeatBalance<double> sys;
  model.assemble(in, p.data(), sys);
  double big[kMaxStates], settled[kMaxStates];
  model.initial_state(big, 20.0, 20.0);
  model.initial_state(settled, 20.0, 20.0);
  exact_step(sys, settled, 1e9);
  for (int k = 0; k < 3; ++k) Sdirk2<double>::step(sys, big, 1e8);
  for (int i = 0; i < model.num_states(); ++i) EXPECT_NEAR(big[i], settled[i], 1e-3 * settled[i]) << i;
}


// The transition matrix the observer propagates its covariance with is the step itself: the step
// is affine in the state, so step(x + d) - step(x) = phi d for any d, with every effect on.
TEST(Integrator, TransitionMatrixIsTheStepsOwnLinearPart) {
  const EffectSet all = (EffectSet{1} << kNumEffects) - 1;
  const Model<double> model(testing::example_motor(), all);
  auto p = default_params<double>();
  p[param_index("sensor_time_constant_s")] = 20.0;
  HeatBalance<double> sys;
  model.assemble(reference_inputs(50.0), p.data(), sys);
  double phi[kMaxStates][kMaxStates];
  ASSERT_TRUE(Sdirk2<double>::transition(sys, 0.1, phi));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> temperature(0.0, 150.0), delta(-20.0, 20.0);
  const int n = model.num_states();
  for (int trial = 0; trial < 20; ++trial) {
    double x[kMaxStates], xd[kMaxStates], d[kMaxStates];
    for (int i = 0; i < n; ++i) {
      x[i] = temperature(rng);
      d[i] = delta(rng);
      xd[i] = x[i] + d[i];
    }
    Sdirk2<double>::step(sys, x, 0.1);
    Sdirk2<double>::step(sys, xd, 0.1);
    for (int i = 0; i < n; ++i) {
      double predicted = 0;
      for (int j = 0; j < n; ++j) predicted += phi[i][j] * d[j];
      EXPECT_NEAR(xd[i] - x[i], predicted, 1e-9) << "state " << i;
    }
  }
}

// step_and_transition() runs its own pass (step_rows, the network's size a constant) and promises
// the bits of step() for the state and of transition() for phi, which run advance(): held here for
// every size of network, on networks that need the LU's row exchanges and on ones that do not.
TEST(Integrator, StepAndTransitionGiveTheBitsOfStepAndOfTransition) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), temperature(0.0, 150.0);
  const double steps[] = {0.1, 1.0, 30.0};
  for (int n = 1; n <= kMaxStates; ++n) {
    int exchanged = 0, trials = 0;
    for (int trial = 0; trial < 40; ++trial) {
      // Half of the networks passive (diagonally dominant: no exchange), half with large couplings
      // and weak diagonals, for which I - gamma h A pivots.
      const bool wild = trial % 2 == 1;
      HeatBalance<double> sys;
      sys.reset(n);
      for (int i = 0; i < n; ++i) {
        sys.c[i] = 50.0 * unit(rng);
        for (int j = 0; j < n; ++j) sys.a[i][j] = (wild ? 5.0 : 0.05) * unit(rng);
        sys.a[i][i] = wild ? 0.01 * unit(rng) : -0.1 * n - 0.5 * (1.0 + unit(rng));
      }
      const double h = steps[trial % 3];
      double x[kMaxStates], y[kMaxStates];
      for (int i = 0; i < n; ++i) x[i] = y[i] = temperature(rng);
      double phi[kMaxStates][kMaxStates], reference[kMaxStates][kMaxStates];
      const bool stepped = Sdirk2<double>::step_and_transition(sys, x, h, phi);
      ASSERT_EQ(stepped, Sdirk2<double>::step(sys, y, h)) << n;
      ASSERT_EQ(stepped, Sdirk2<double>::transition(sys, h, reference)) << n;
      if (!stepped) continue;
      ++trials;
      for (int i = 0; i < n; ++i) {
        EXPECT_EQ(std::memcmp(&x[i], &y[i], sizeof x[i]), 0) << "n " << n << " trial " << trial << " state " << i;
        for (int j = 0; j < n; ++j)
          EXPECT_EQ(std::memcmp(&phi[i][j], &reference[i][j], sizeof phi[i][j]), 0)
              << "n " << n << " trial " << trial << " phi " << i << "," << j;
      }
      // Did this network's factorisation exchange rows? (The same matrix the integrator factors.)
      internal::SmallLu<double> lu;
      double m[kMaxStates][kMaxStates];
      const double gh = Sdirk2<double>::kGamma * h;
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) m[i][j] = -gh * sys.a[i][j];
        m[i][i] += 1.0;
      }
      ASSERT_TRUE(lu.factor(m, n));
      for (int k = 0; k < n; ++k) exchanged += lu.swap[k] != k ? 1 : 0;
    }
    EXPECT_GE(trials, 30) << n;
    if (n > 1) {
      EXPECT_GT(exchanged, 0) << "no network of size " << n << " made the LU exchange rows";
    }
  }
}

// step_with_responses moves the state exactly as step() does, and each response as the step moves
// a change of the start: step(x + d) - step(x), for any d (the initial offsets' one-run estimate).
TEST(Integrator, ResponsesSteppedBesideTheStateAreWhatAChangedStartMovesBy) {
  const EffectSet all = (EffectSet{1} << kNumEffects) - 1;
  const Model<double> model(testing::example_motor(), all);
  auto p = default_params<double>();
  p[param_index("sensor_time_constant_s")] = 20.0;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> temperature(0.0, 150.0), delta(-20.0, 20.0);
  const int n = model.num_states();
  double x[kMaxStates], alone[kMaxStates], shifted[2][kMaxStates], d[2][kMaxStates];
  for (int i = 0; i < n; ++i) {
    x[i] = alone[i] = temperature(rng);
    for (int r = 0; r < 2; ++r) {
      d[r][i] = delta(rng);
      shifted[r][i] = x[i] + d[r][i];
    }
  }
  double* responses[2] = {d[0], d[1]};
  Model<double>::StepWorkspace<double> work;
  for (int k = 0; k < 600; ++k) {  // a minute of the reference case, everything moving
    const auto in = model.prepare(reference_inputs(0.1 * k));
    ASSERT_TRUE(model.step_with_responses(x, in, p.data(), 0.1, work, responses, 2));
    ASSERT_TRUE(model.step(alone, in, p.data(), 0.1, work));
    for (double* s : shifted) ASSERT_TRUE(model.step(s, in, p.data(), 0.1, work));
  }
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(x[i], alone[i]) << "state " << i << ": the state's own step is step()'s, bit for bit";
    for (int r = 0; r < 2; ++r) EXPECT_NEAR(shifted[r][i] - alone[i], d[r][i], 1e-9) << "response " << r << ", state " << i;
  }
  EXPECT_GT(std::abs(d[0][0]), 1e-3) << "a minute in, the start still shows";
}

}  // namespace
}  // namespace lptn
