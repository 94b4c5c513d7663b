// The one fixed-step integrator of the project, used by the trainer's simulation and by the
// firmware's prediction alike.
//
// Method: the two-stage, second-order, L-stable singly diagonally implicit Runge-Kutta method of
// Alexander (1977), gamma = 1 - 1/sqrt(2), applied to dx/dt = A x + c with A and c held over the
// step. Why this one:
//  - the network's A changes every step with airflow and speed and can be stiff (a large
//    stator-core conductance against a small winding capacitance, a fast sensor lag); an explicit
//    method would need a step bounded by the fastest time constant, this one is stable for any
//    step and any passive parameter set (A-stable, and algebraically stable since gamma >= 1/4,
//    so it cannot amplify a dissipative system even as A changes from step to step);
//  - L-stability damps stiff modes in one step instead of letting them ring (trapezoidal rule);
//  - second order keeps it within 0.01 K of the exact solution at 0.1 s (see the tests);
//  - for a linear system both stages share one matrix, I - gamma h A: one small LU per step.
#pragma once

#include "lptn/heat_balance.hpp"
#include "lptn/internal/small_lu.hpp"

namespace lptn {

template <class T>
struct Sdirk2 {
  static constexpr double kGamma = 0.29289321881345247560;  // 1 - 1/sqrt(2)

  // Advances x (sys.n entries) by h seconds. sys must be finish()ed (rate form). Returns false
  // (and leaves x unchanged) only if the stage matrix is singular.
  template <class R>
  static bool step(const HeatBalance<T>& sys, T* x, const R& h) {
    internal::SmallLu<T> lu;
    return step(sys, x, h, lu);
  }
  // The same with the factorisation's storage given: a caller that steps many times keeps one,
  // so that a Jet scalar's 64 entries are not constructed (zeroed) again every step.
  template <class R>
  static bool step(const HeatBalance<T>& sys, T* x, const R& h, internal::SmallLu<T>& lu) {
    if (!factor_stage_matrix(sys, h, lu)) return false;
    advance(sys, lu, x, h, true);
    return true;
  }

  // The same step as an affine map, x_new = phi x + (the step from x = 0), with phi built column
  // by column from the very arithmetic step() does (the input term c left out), so that a Kalman
  // filter propagates its covariance through exactly the step that moves its state. Returns false
  // (phi untouched) if the stage matrix is singular.
  template <class R>
  static bool transition(const HeatBalance<T>& sys, const R& h, T (&phi)[kMaxStates][kMaxStates]) {
    internal::SmallLu<T> lu;
    return transition(sys, h, phi, lu);
  }
  // The same, leaving the stage matrix's factorisation in lu for step_factored(): a filter that
  // moves its state and its covariance through one step factors it once.
  template <class R>
  static bool transition(const HeatBalance<T>& sys, const R& h, T (&phi)[kMaxStates][kMaxStates],
                         internal::SmallLu<T>& lu) {
    if (!factor_stage_matrix(sys, h, lu)) return false;
    const int n = sys.n;
    for (int j = 0; j < n; ++j) {
      T column[kMaxStates];
      for (int i = 0; i < n; ++i) column[i] = T(i == j ? 1 : 0);
      advance(sys, lu, column, h, false);
      for (int i = 0; i < n; ++i) phi[i][j] = column[i];
    }
    return true;
  }
  // step() of x, and of `count` more states without the input term, through one factorisation:
  // how x's response to a change of its start moves (x is affine in its start with A and c held),
  // for a caller that wants both, at the cost of one assembly and one factorisation a step.
  template <class R>
  static bool step_with_responses(const HeatBalance<T>& sys, T* x, T* const* responses, int count, const R& h,
                                  internal::SmallLu<T>& lu) {
    if (!factor_stage_matrix(sys, h, lu)) return false;
    advance(sys, lu, x, h, true);
    for (int r = 0; r < count; ++r) advance(sys, lu, responses[r], h, false);
    return true;
  }
  // step() with the factorisation transition() left for the same sys and h.
  template <class R>
  static void step_factored(const HeatBalance<T>& sys, const internal::SmallLu<T>& lu, T* x, const R& h) {
    advance(sys, lu, x, h, true);
  }

 private:
  // Both stages share one matrix, I - gamma h A.
  template <class R>
  static bool factor_stage_matrix(const HeatBalance<T>& sys, const R& h, internal::SmallLu<T>& lu) {
    const int n = sys.n;
    const T gh = T(kGamma * h);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) lu.lu[i][j] = -gh * sys.a[i][j];
      lu.lu[i][i] += T(1);
    }
    return lu.factor_in_place(n);
  }

  // The two stages; with_input = false drops c (the homogeneous part, for transition()).
  template <class R>
  static void advance(const HeatBalance<T>& sys, const internal::SmallLu<T>& lu, T* x, const R& h, bool with_input) {
    const int n = sys.n;
    auto rate = [&](int i, const T* at) {  // sys.derivative(), with or without c
      T p = with_input ? sys.c[i] : T(0);
      for (int j = 0; j < n; ++j) p += sys.a[i][j] * at[j];
      return p;
    };
    // Stage 1: k1 = A (x + gamma h k1) + c.
    T k1[kMaxStates];
    for (int i = 0; i < n; ++i) k1[i] = rate(i, x);
    lu.solve(k1);
    // Stage 2: k2 = A (x + (1 - gamma) h k1 + gamma h k2) + c.
    T x1[kMaxStates];
    const T w1 = T((1.0 - kGamma) * h);
    for (int i = 0; i < n; ++i) x1[i] = x[i] + w1 * k1[i];
    T k2[kMaxStates];
    for (int i = 0; i < n; ++i) k2[i] = rate(i, x1);
    lu.solve(k2);
    // Stiffly accurate: the new state is the second stage's.
    const T w2 = T(kGamma * h);
    for (int i = 0; i < n; ++i) x[i] = x1[i] + w2 * k2[i];
  }
};

}  // namespace lptn
