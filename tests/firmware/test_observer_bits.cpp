// The observer's prediction against the plain computation it stands for: every sensitivity column
// from a whole network assembled and finished at the stepped parameters. The observer finishes
// and evaluates only the rows a stepped parameter changed; this holds it to the plain
// computation's bits (state, covariance, cross-covariance) step after step, for every effect,
// random inputs and parameters, with fusions in between.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "lptn_testing/converter.hpp"
#include "lptn/firmware/observer.hpp"

namespace lptn::fw {
namespace {

struct FilterState {
  double x[kMaxFilterStates]{};
  double p[kMaxFilterStates][kMaxFilterStates]{};
  double cross[kMaxFilterStates][kNumParams]{};
};

FilterState snapshot(const Observer<double>& o) {
  FilterState s;
  const int nf = o.num_filter_states();
  for (int i = 0; i < nf; ++i) {
    s.x[i] = o.state()[i];
    for (int j = 0; j < nf; ++j) s.p[i][j] = o.covariance(i, j);
    for (int c = 0; c < o.num_consider(); ++c) s.cross[i][c] = o.cross_covariance(i, c);
  }
  if (!o.estimates_cooling()) s.x[o.num_states()] = o.state()[o.num_states()];
  return s;
}

// Observer::predict as the textbook has it: whole networks, dense sums.
bool plain_predict(const Observer<double>& o, FilterState& s, const Inputs<double>& in, const double* params,
                   bool freeze_cooling) {
  const Model<double>& model = o.model();
  const ObserverSettings<double>& settings = o.settings();
  const int n = o.num_states();
  const int nf = o.num_filter_states();
  const int m = o.num_consider();
  ParamVector<double> p;
  for (int i = 0; i < kNumParams; ++i) p[i] = params[i];
  const double factor = std::exp(s.x[n]);
  for (int i : kConductancesToAir) p[i] = params[i] * factor;
  HeatBalance<double> sys, stepped;
  model.assemble(in, p.data(), sys);
  double rate[kMaxStates];
  for (int i = 0; i < n; ++i) rate[i] = sys.derivative(i, s.x);
  double phi[kMaxFilterStates][kMaxFilterStates]{};
  if (settings.estimate_cooling) {
    for (int i : kConductancesToAir) p[i] = params[i] * factor * 1.1;
    model.assemble(in, p.data(), stepped);
    const double scale = settings.dt_s / std::log(1.1);
    for (int i = 0; i < n; ++i) phi[i][n] = (stepped.derivative(i, s.x) - rate[i]) * scale;
    phi[n][n] = 1;
    for (int i : kConductancesToAir) p[i] = params[i] * factor;
  }
  static double psi[kMaxFilterStates][kNumParams];  // the cooling factor's row stays 0: no parameter moves it
  std::memset(psi, 0, sizeof psi);
  for (int c = 0; c < m; ++c) {
    const int j = o.consider_param(c);
    const double base = p[j];
    p[j] = base * kParamStep;
    model.assemble(in, p.data(), stepped);
    p[j] = base;
    const double scale = settings.dt_s / (kParamStep - 1.0);
    for (int i = 0; i < n; ++i) psi[i][c] = (stepped.derivative(i, s.x) - rate[i]) * scale;
  }
  double model_phi[kMaxStates][kMaxStates];
  if (!Sdirk2<double>::step_and_transition(sys, s.x, settings.dt_s, model_phi)) return false;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) phi[i][j] = model_phi[i][j];

  double tmp[kMaxFilterStates][kMaxFilterStates];
  for (int i = 0; i < nf; ++i)
    for (int j = 0; j < nf; ++j) {
      double acc = 0;
      for (int k = 0; k < nf; ++k) acc += phi[i][k] * s.p[k][j];
      tmp[i][j] = acc;
    }
  static double phi_c[kMaxFilterStates][kNumParams];
  for (int i = 0; i < nf; ++i)
    for (int c = 0; c < m; ++c) {
      double acc = 0;
      for (int k = 0; k < nf; ++k) acc += phi[i][k] * s.cross[k][c];
      phi_c[i][c] = acc;
    }
  for (int i = 0; i < nf; ++i) {
    double psi_s[kNumParams];
    for (int c = 0; c < m; ++c) {
      const double sd = settings.param_ln_std[o.consider_param(c)];
      psi_s[c] = psi[i][c] * sd * sd;
    }
    for (int j = 0; j < nf; ++j) {
      double acc = 0;
      for (int k = 0; k < nf; ++k) acc += tmp[i][k] * phi[j][k];
      for (int c = 0; c < m; ++c) acc += phi_c[i][c] * psi[j][c] + psi[i][c] * phi_c[j][c] + psi_s[c] * psi[j][c];
      s.p[i][j] = acc;
    }
    for (int c = 0; c < m; ++c) s.cross[i][c] = phi_c[i][c] + psi_s[c];
  }
  for (int i = 0; i < n; ++i) {
    const double q = i < kNumNodes ? settings.process_noise_k_per_sqrt_s[i] : settings.process_noise_extra_k_per_sqrt_s;
    s.p[i][i] += q * q * settings.dt_s;
  }
  if (settings.estimate_cooling && !freeze_cooling) {
    const double q = settings.cooling_process_noise_per_sqrt_s;
    s.p[n][n] += q * q * settings.dt_s;
  }
  for (int i = 0; i < nf; ++i)
    for (int j = i + 1; j < nf; ++j) {
      const double mid = 0.5 * (s.p[i][j] + s.p[j][i]);
      s.p[i][j] = mid;
      s.p[j][i] = mid;
    }
  return true;
}

// Entries whose bits differ (what the observer holds against the plain computation).
int differing_bits(const Observer<double>& o, const FilterState& want) {
  const FilterState got = snapshot(o);
  const int nf = o.num_filter_states();
  int differ = 0;
  for (int i = 0; i < nf; ++i) {
    differ += std::memcmp(&got.x[i], &want.x[i], sizeof(double)) != 0;
    for (int j = 0; j < nf; ++j) differ += std::memcmp(&got.p[i][j], &want.p[i][j], sizeof(double)) != 0;
    for (int c = 0; c < o.num_consider(); ++c)
      differ += std::memcmp(&got.cross[i][c], &want.cross[i][c], sizeof(double)) != 0;
  }
  return differ;
}

Inputs<double> random_inputs(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Inputs<double> in;
  const bool standing = u(rng) < 0.1;  // pulses off: no iron, stray or harmonic loss
  in.speed_rpm = standing ? 0.0 : 3500.0 * u(rng);
  in.frequency_hz = standing ? 0.0 : in.speed_rpm * 2.0 / 60.0 + 3.0 * u(rng);
  in.current_a = standing ? 0.0 : 20.0 + 180.0 * u(rng);
  in.has_torque = u(rng) < 0.5;
  in.torque_nm = 3000.0 * (u(rng) - 0.2);
  in.has_voltage = u(rng) < 0.5;
  in.voltage_v = 2200.0 * u(rng);
  in.airflow_m3s = u(rng) < 0.1 ? 0.0 : 1.6 * u(rng);
  in.ambient_c = -20.0 + 60.0 * u(rng);
  return in;
}

void expect_plain_bits(EffectSet effects, bool estimate_cooling, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  ObserverSettings<double> settings;
  settings.estimate_cooling = estimate_cooling;
  // The paper's and the enabled effect's parameters consider states, and every fifth of the
  // others too: their columns are all +0. (At most 64: the observer's masks.)
  int consider = 0;
  for (int j = 0; j < kNumParams; ++j) {
    const int e = effect_of_param(j);
    if (e < 0 || (effects & effect_bit(e)) != 0 || j % 5 == 0) {
      settings.param_ln_std[j] = 0.02 + 0.2 * u(rng);
      ++consider;
    }
  }
  ASSERT_LE(consider, 64);
  Observer<double> o(testing::example_motor(), effects, settings);
  o.initialize(30.0, true, 28.0, true);
  ParamVector<double> params = testing::true_params();
  for (int j = 0; j < kNumParams; ++j) params[j] *= 0.8 + 0.4 * u(rng);

  int differ = 0, steps = 0, moved = 0;
  for (int step = 0; step < 600 && differ == 0; ++step) {
    const Inputs<double> in = random_inputs(rng);
    const bool freeze = u(rng) < 0.2;
    FilterState want = snapshot(o);
    const double before = want.p[kStatorWinding][kStatorWinding];
    const bool plain_ok = plain_predict(o, want, in, params.data(), freeze);
    ASSERT_EQ(o.predict(in, params.data(), freeze), plain_ok);
    differ += differing_bits(o, want);
    moved += o.covariance(kStatorWinding, kStatorWinding) != before;
    ++steps;
    if (step % 7 == 0) {  // a reading now and then, so that P and C are not only grown
      Fusion<double> f = o.test(o.stator_sensor_c() + 2.0 * (u(rng) - 0.5));
      o.fuse(f);
    }
  }
  EXPECT_EQ(differ, 0) << "effects " << effects << ", cooling " << estimate_cooling << ": after " << steps
                       << " steps";
  EXPECT_GT(moved, steps / 2);  // the covariance did move: the comparison was not of constants
}

TEST(ObserverBits, ThePredictionIsThePlainComputationBitForBit) {
  unsigned seed = 1;
  for (bool cooling : {true, false}) {
    expect_plain_bits(0, cooling, seed++);
    for (int e = 0; e < kNumEffects; ++e) expect_plain_bits(effect_bit(e), cooling, seed++);
  }
}

// A spread that is not finite makes the covariance NaN: the same NaN.
TEST(ObserverBits, ANonFiniteSpreadGivesThePlainComputationsBitsToo) {
  std::mt19937 rng(7);
  ObserverSettings<double> settings;
  settings.param_ln_std[kLambda1s] = 0.1;
  settings.param_ln_std[kLambda12r] = INFINITY;
  Observer<double> o(testing::example_motor(), 0, settings);
  o.initialize(30.0, true, 28.0, true);
  const ParamVector<double> params = testing::true_params();
  for (int step = 0; step < 5; ++step) {
    FilterState want = snapshot(o);
    const Inputs<double> in = random_inputs(rng);
    ASSERT_EQ(o.predict(in, params.data()), plain_predict(o, want, in, params.data(), false));
    EXPECT_EQ(differing_bits(o, want), 0) << "step " << step;
  }
}

}  // namespace
}  // namespace lptn::fw
