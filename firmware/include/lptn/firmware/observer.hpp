// The observer core: the shared model and integrator as a Kalman filter.
//
// Prediction is the model's own step (common/: Model::assemble and Sdirk2, the very code the
// trainer simulates with); the covariance goes through the same step's transition matrix,
//     x+ = step(x, u),   P+ = Phi P Phi' + Q,   Q = diag(q_i^2 dt).
// Correction fuses one scalar reading, the stator winding sensor (the state it reads is the
// layout's stator_sensor_state: node 1, or the sensor's own state with sensor_lag):
//     nu = y - x_s,  S = P_ss + r^2,  K = P e_s / S,  x += K nu,  P = (I - K e_s') P (I - K e_s')' + r^2 K K'
// (Joseph form: stays symmetric and positive in float). A reading whose test ratio
// nu^2 / (S gate^2) exceeds one is rejected, as PX4's EKF2 gates its fusions.
//
// Cooling health: one more state after the model's, theta = ln(cooling factor), the factor on
// every conductance to the cooling air (kConductancesToAir, as the fleet calibration fits one per
// motor). A random walk, slow by its process noise; the prediction runs on the calibrated
// parameters with those conductances times exp(theta), and its column of Phi is the step's
// sensitivity dt d(dx/dt)/d theta, evaluated as a difference of rates (not of states, which a
// float could not resolve). The stator sensor then corrects theta through its covariance with the
// stator nodes: a motor whose winding runs hotter than its load explains is cooled less. While no
// reading is fused (open loop), the caller freezes it: no process noise, so the estimate and its
// spread stand until readings return.
// Parameter uncertainty (Schmidt-Kalman "consider" filter): each parameter with a spread
// (settings.param_ln_std, from the calibration's standard errors: parameter_uncertainty.hpp) is a
// consider state d_j = ln(p_j / calibrated p_j) with prior variance s_j^2. Its value stays 0 (the
// calibrated one) and it is never updated, but its cross-covariance with the states C = P_x,d is
// carried, so each node's reported spread includes what the parameters' errors do to it:
//     C+ = Phi C + Psi S,   P+ = Phi P Phi' + Phi C Psi' + Psi C' Phi' + Psi S Psi' + Q
// with Psi the step's sensitivity dt d(dx/dt)/d d_j (a difference of rates, as theta's column) and
// S = diag(s_j^2). A fusion updates C with the states, C -= K C_s, so the stator reading's
// information about the parameters' combination lowers every correlated node's spread; S stands.
// Why consider and not estimate the parameters: the stator winding alone cannot pin six
// conductances on board (the calibration with hours of data could not always), and an estimated
// parameter would drift with the model's transient errors, as theta's slow walk is there to avoid.
// Plain library: settings struct, setters, no heap, no exceptions, bounded loops.
#pragma once

#include <cmath>
#include <cstring>

#include "lptn/model.hpp"

namespace lptn::fw {

// The model's states and the cooling factor's.
inline constexpr int kMaxFilterStates = kMaxStates + 1;
// The cooling factor stays within 1/5..5 (ln 5): beyond, no cooling this model describes; held
// there, the network stays a passive one whatever the readings do.
inline constexpr double kMaxLnCoolingFactor = 1.6094379124341003;
// The step of a parameter for its sensitivity column: large enough for a float to resolve the
// difference of rates, small enough for first order in a nonlinear one.
inline constexpr double kParamStep = 1.1;

template <class T>
struct ObserverSettings {
  T dt_s = T(0.1);
  T sensor_noise_k = T(0.5);  // stator winding sensor, 1 sigma (PT100 + quantization)
  T rotor_sensor_noise_k = T(1.0);
  // How fast the model's own error may grow: a random walk per node, K per sqrt(s). 0.02 K/sqrt(s)
  // lets a node drift about 1.2 K in an hour unobserved, a little more than the calibrated
  // model's error on unseen cycles.
  T process_noise_k_per_sqrt_s[kNumNodes] = {T(0.02), T(0.02), T(0.03), T(0.03)};
  T process_noise_extra_k_per_sqrt_s = T(0.02);  // effects' extra states (e.g. the lagged sensor)
  T initial_std_unmeasured_k = T(5);  // every node, started without a stator reading
  // Nodes no sensor sees, started at the stator's reading (a soaked motor, as the trainer starts
  // every cycle). 5 K unless the calibration says better (apply_calibration_uncertainty).
  T initial_std_soaked_k = T(5);
  T gate_sigma = T(4);  // innovations beyond this many predicted standard deviations are rejected
  // Cooling factor (ln units). The start: nominal (the calibration's own motor), 1 sigma 15 %, as
  // far as motors of a type scatter new and a filter clogs between services. The random walk lets
  // the factor move about 6 % in an hour: a filter clogs over days, a blower fails in a moment but
  // then stays failed, and a faster walk would chase the model's own transient errors.
  bool estimate_cooling = true;
  T cooling_initial_std = T(0.15);
  T cooling_process_noise_per_sqrt_s = T(0.001);
  // Each parameter's 1-sigma spread in ln terms (parameter_ln_std); 0: taken as exact, no consider
  // state. All zero: the filter of process noise alone.
  T param_ln_std[kNumParams]{};
};

// One fusion's figures, published every tick for the last reading (EKF2's innovation reporting).
template <class T>
struct Fusion {
  T innovation_k = T(0);      // reading minus prediction
  T innovation_std_k = T(0);  // sqrt(S)
  T test_ratio = T(0);        // nu^2 / (S gate^2); > 1 rejected
  bool accepted = false;      // fused
};

template <class T>
class Observer {
 public:
  Observer(const MotorConstants<T>& motor, EffectSet effects, const ObserverSettings<T>& settings)
      : model_(motor, effects), settings_(settings) {}

  const Model<T>& model() const { return model_; }
  const ObserverSettings<T>& settings() const { return settings_; }
  int num_states() const { return model_.num_states(); }
  // The model's states and, when estimated, the cooling factor's after them.
  int num_filter_states() const { return model_.num_states() + (settings_.estimate_cooling ? 1 : 0); }

  // Start as the trainer does (trainer/model/simulate.hpp): the stator nodes at the stator
  // reading, the rotor nodes at the rotor reading, or at the stator's where the rotor is not
  // measured (a motor that has stood is soaked through). Unmeasured nodes start uncertain; so
  // does everything when there was no stator reading to start from.
  void initialize(T stator_c, bool stator_measured, T rotor_c, bool rotor_measured) {
    model_.initial_state(x_, stator_c, rotor_measured ? rotor_c : stator_c);
    const int n = num_states();
    for (int i = 0; i < kMaxFilterStates; ++i)
      for (int j = 0; j < kMaxFilterStates; ++j) p_[i][j] = T(0);
    // The start's errors (the readings') are independent of the parameters'.
    num_consider_ = 0;
    for (int j = 0; j < kNumParams; ++j)
      if (settings_.param_ln_std[j] > T(0)) consider_[num_consider_++] = j;
    for (int i = 0; i < kMaxFilterStates; ++i)
      for (int c = 0; c < kNumParams; ++c) cross_[i][c] = T(0);
    x_[n] = T(0);  // ln 1: nominal cooling
    if (settings_.estimate_cooling) p_[n][n] = settings_.cooling_initial_std * settings_.cooling_initial_std;
    const T unmeasured = stator_measured ? settings_.initial_std_soaked_k * settings_.initial_std_soaked_k
                                         : settings_.initial_std_unmeasured_k * settings_.initial_std_unmeasured_k;
    const T stator = stator_measured ? settings_.sensor_noise_k * settings_.sensor_noise_k : unmeasured;
    const T rotor = rotor_measured ? settings_.rotor_sensor_noise_k * settings_.rotor_sensor_noise_k : unmeasured;
    for (int i = 0; i < n; ++i) p_[i][i] = unmeasured;
    p_[kStatorWinding][kStatorWinding] = stator;
    p_[model_.layout().stator_sensor_state][model_.layout().stator_sensor_state] = stator;
    p_[kRotorWinding][kRotorWinding] = rotor;
  }

  // One step of dt with the inputs held over it. Returns false (state and covariance unchanged)
  // only if the step's matrix was singular, which a passive parameter set cannot produce.
  // freeze_cooling: no reading is fused (open loop), so the cooling factor and its spread stand.
  bool predict(const Inputs<T>& in, const T* params, bool freeze_cooling = false) {
    using std::exp;
    using std::log;
    const int n = num_states();
    ParamVector<T> p;
    for (int i = 0; i < kNumParams; ++i) p[i] = params[i];
    const T factor = exp(x_[n]);
    for (int i : kConductancesToAir) p[i] = params[i] * factor;
    // The inputs' share of the step (losses, airflow), once for the step and its sensitivities.
    const typename Model<T>::PreparedInputs step = model_.prepare(in);
    // The network in power units, kept for the stepped sets below to be compared with row by row.
    // (The networks are members: constructing three on every step zeroed 240 numbers.)
    HeatBalance<T>& unscaled = unscaled_;
    HeatBalance<T>& sys = sys_;
    HeatBalance<T>& stepped = stepped_;
    model_.assemble_in_power_units(step, p.data(), unscaled);
    sys.finish_from(unscaled);
    losses_ = step.losses;
    T phi[kMaxFilterStates][kMaxFilterStates]{};
    // The rates at x_, and one network for every stepped set below (assembled in full: every
    // row it reads is set).
    T rate[kMaxStates];
    for (int i = 0; i < n; ++i) rate[i] = sys.derivative(i, x_);
    if (settings_.estimate_cooling) {
      // The rates are linear in the factor, so a step of 10 % gives d rate / d theta exactly,
      // up to rounding, at magnitudes a float resolves.
      constexpr double kStep = 1.1;
      for (int i : kConductancesToAir) p[i] = params[i] * factor * T(kStep);
      model_.assemble_in_power_units(step, p.data(), stepped);
      const T scale = settings_.dt_s / T(log(kStep));
      for (int i = 0; i < n; ++i) phi[i][n] = rate_difference(stepped, unscaled, rate, i) * scale;
      phi[n][n] = T(1);
      for (int i : kConductancesToAir) p[i] = params[i] * factor;
    }
    // Each consider parameter's column: a 10 % step of the parameter, divided by the step's 0.1 in
    // p (the rates are linear in every conductance and loss factor, so this is d rate / d ln p at
    // the calibrated value; for the effects' exponents, first order).
    T (&psi)[kMaxFilterStates][kNumParams] = psi_;  // a member: kNumParams columns are too many for a small stack
    for (int c = 0; c < num_consider_; ++c) {
      const int j = consider_[c];
      const T base = p[j];
      p[j] = base * T(kParamStep);
      model_.assemble_in_power_units(step, p.data(), stepped);
      p[j] = base;
      const T scale = settings_.dt_s / T(kParamStep - 1.0);
      for (int i = 0; i < n; ++i) psi[i][c] = rate_difference(stepped, unscaled, rate, i) * scale;
    }
    // The step of the state and its transition matrix last: the columns above are rates at the
    // step's start.
    T model_phi[kMaxStates][kMaxStates];
    if (!Sdirk2<T>::step_and_transition(sys, x_, settings_.dt_s, model_phi)) return false;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) phi[i][j] = model_phi[i][j];
    propagate_covariance(phi, psi, freeze_cooling);
    return true;
  }

  // A stator winding reading against the prediction: innovation, its spread and the test ratio.
  Fusion<T> test(T reading_c) const {
    using std::sqrt;
    const int s = model_.layout().stator_sensor_state;
    const T innovation_var = p_[s][s] + settings_.sensor_noise_k * settings_.sensor_noise_k;
    Fusion<T> f;
    f.innovation_k = reading_c - x_[s];
    f.innovation_std_k = sqrt(innovation_var);
    f.test_ratio = f.innovation_k * f.innovation_k / (innovation_var * settings_.gate_sigma * settings_.gate_sigma);
    return f;
  }

  // Fuses a tested reading (the caller decides, on the test ratio and the sensor's health).
  void fuse(Fusion<T>& f) {
    const int s = model_.layout().stator_sensor_state;
    update(s, f.innovation_k, f.innovation_std_k * f.innovation_std_k, settings_.sensor_noise_k * settings_.sensor_noise_k);
    const T kMaxLn = T(kMaxLnCoolingFactor);
    T& theta = x_[num_states()];
    theta = theta > kMaxLn ? kMaxLn : (theta < -kMaxLn ? -kMaxLn : theta);
    f.accepted = true;
  }

  const T* state() const { return x_; }
  T node_c(int node) const { return x_[node]; }
  T node_std_k(int node) const {
    using std::sqrt;
    return sqrt(p_[node][node] > T(0) ? p_[node][node] : T(0));
  }
  T stator_sensor_c() const { return model_.stator_sensor(x_); }
  bool estimates_cooling() const { return settings_.estimate_cooling; }
  // The cooling factor (1: as calibrated) and its standard deviation (first order in theta's).
  T cooling_factor() const {
    using std::exp;
    return exp(x_[num_states()]);
  }
  T cooling_factor_std_ln() const {
    using std::sqrt;
    const int c = num_states();
    return sqrt(p_[c][c] > T(0) ? p_[c][c] : T(0));
  }
  T cooling_factor_std() const { return cooling_factor() * cooling_factor_std_ln(); }
  // The filter's covariance (states, then the cooling factor's), and the cross-covariance of the
  // states with consider parameter c (parameter index consider_param(c)).
  T covariance(int i, int j) const { return p_[i][j]; }
  int num_consider() const { return num_consider_; }
  int consider_param(int c) const { return consider_[c]; }
  T cross_covariance(int i, int c) const { return cross_[i][c]; }
  const OperatingLosses<T>& losses() const { return losses_; }

 private:
  // Row i's rate in `stepped` (a network in power units at stepped parameters, finished here where
  // needed) minus the calibrated rate. A parameter enters one or two rows of the network, so most
  // rows of a stepped set are those of `unscaled` (the calibrated network in power units) in every
  // bit: such a row would finish to the calibrated row's bits and give the calibrated rate, so its
  // difference is rate - rate (+0 for a finite rate), with no division and no sum. Every row gives
  // the bits finishing the whole network gives.
  T rate_difference(HeatBalance<T>& stepped, const HeatBalance<T>& unscaled, const T* rate, int i) const {
    bool same = same_bits(stepped.c[i], unscaled.c[i]) && same_bits(stepped.capacitance[i], unscaled.capacitance[i]);
    for (int j = 0; same && j < stepped.n; ++j) same = same_bits(stepped.a[i][j], unscaled.a[i][j]);
    if (same) return rate[i] - rate[i];
    stepped.finish_row(i);
    return stepped.derivative(i, x_) - rate[i];
  }
  static bool same_bits(const T& a, const T& b) { return std::memcmp(&a, &b, sizeof(T)) == 0; }

  void propagate_covariance(const T (&phi)[kMaxFilterStates][kMaxFilterStates],
                            const T (&psi)[kMaxFilterStates][kNumParams], bool freeze_cooling) {
    const int n = num_filter_states();
    const int m = num_consider_;
    T tmp[kMaxFilterStates][kMaxFilterStates];  // Phi P
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        T acc = T(0);
        for (int k = 0; k < n; ++k) acc += phi[i][k] * p_[k][j];
        tmp[i][j] = acc;
      }
    T (&phi_c)[kMaxFilterStates][kNumParams] = phi_cross_;  // Phi C
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < m; ++c) {
        T acc = T(0);
        for (int k = 0; k < n; ++k) acc += phi[i][k] * cross_[k][c];
        phi_c[i][c] = acc;
      }
    // Row by row: P's row i needs row i of Psi S, and C's row i is no longer read once Phi C is made.
    for (int i = 0; i < n; ++i) {
      T psi_s[kNumParams];  // row i of Psi S (psi s s, in that order, as the sums always took it)
      for (int c = 0; c < m; ++c) {
        const T s = settings_.param_ln_std[consider_[c]];
        psi_s[c] = psi[i][c] * s * s;
      }
      for (int j = 0; j < n; ++j) {
        T acc = T(0);
        for (int k = 0; k < n; ++k) acc += tmp[i][k] * phi[j][k];
        // + Phi C Psi' + Psi C' Phi' + Psi S Psi'
        for (int c = 0; c < m; ++c) acc += phi_c[i][c] * psi[j][c] + psi[i][c] * phi_c[j][c] + psi_s[c] * psi[j][c];
        p_[i][j] = acc;
      }
      for (int c = 0; c < m; ++c) cross_[i][c] = phi_c[i][c] + psi_s[c];
    }
    for (int i = 0; i < num_states(); ++i) {
      const T q = i < kNumNodes ? settings_.process_noise_k_per_sqrt_s[i] : settings_.process_noise_extra_k_per_sqrt_s;
      p_[i][i] += q * q * settings_.dt_s;
    }
    if (settings_.estimate_cooling && !freeze_cooling) {
      const T q = settings_.cooling_process_noise_per_sqrt_s;
      p_[num_states()][num_states()] += q * q * settings_.dt_s;
    }
    symmetrize();
  }

  // Joseph-form update for the scalar measurement of state s.
  void update(int s, T innovation, T innovation_var, T r) {
    const int n = num_filter_states();
    T k[kMaxFilterStates];
    for (int i = 0; i < n; ++i) k[i] = p_[i][s] / innovation_var;
    for (int i = 0; i < n; ++i) x_[i] += k[i] * innovation;
    // A = I - k e_s'; P = A P A' + r k k'
    T ap[kMaxFilterStates][kMaxFilterStates];
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) ap[i][j] = p_[i][j] - k[i] * p_[s][j];
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) p_[i][j] = ap[i][j] - ap[i][s] * k[j] + r * k[i] * k[j];
    // The consider states stand; their cross-covariance follows the states': C = A C.
    for (int c = 0; c < num_consider_; ++c) {
      const T cs = cross_[s][c];
      for (int i = 0; i < n; ++i) cross_[i][c] -= k[i] * cs;
    }
    symmetrize();
  }

  void symmetrize() {
    const int n = num_filter_states();
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        const T m = T(0.5) * (p_[i][j] + p_[j][i]);
        p_[i][j] = m;
        p_[j][i] = m;
      }
  }

  Model<T> model_;
  ObserverSettings<T> settings_;
  T x_[kMaxFilterStates]{};  // the model's states, then theta
  T p_[kMaxFilterStates][kMaxFilterStates]{};
  // The consider parameters (indices into the parameter vector) and their cross-covariance with
  // the states, column c for parameter consider_[c].
  int consider_[kNumParams]{};
  int num_consider_ = 0;
  T cross_[kMaxFilterStates][kNumParams]{};
  HeatBalance<T> unscaled_, sys_, stepped_;      // predict's scratch: the networks of the step
  T psi_[kMaxFilterStates][kNumParams]{};        // predict's scratch: the step's parameter sensitivities
  T phi_cross_[kMaxFilterStates][kNumParams]{};  // propagate's scratch: Phi C
  OperatingLosses<T> losses_{};
};

}  // namespace lptn::fw
