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
    T* const columns[1] = {x};
    advance<1>(sys, lu, columns, 1, 1, h);
    return true;
  }

  // The same step as an affine map, x_new = phi x + (the step from x = 0), with phi built column
  // by column from the very arithmetic step() does (the input term c left out), so that a Kalman
  // filter propagates its covariance through exactly the step that moves its state. Returns false
  // (phi untouched) if the stage matrix is singular.
  template <class R>
  static bool transition(const HeatBalance<T>& sys, const R& h, T (&phi)[kMaxStates][kMaxStates]) {
    internal::SmallLu<T> lu;
    if (!factor_stage_matrix(sys, h, lu)) return false;
    step_and_columns(sys, lu, nullptr, h, phi);
    return true;
  }
  // step() of x and transition() of the same step, through one factorisation and one pass over
  // the stages: what a Kalman filter needs of a step (its state moved, its covariance's matrix).
  // x and phi get the bits step() and transition() give them. Returns false (x and phi
  // untouched) if the stage matrix is singular.
  // The pass is step_rows(), with the network's size a constant: the observer's every tick.
  template <class R>
  static bool step_and_transition(const HeatBalance<T>& sys, T* x, const R& h, T (&phi)[kMaxStates][kMaxStates]) {
    internal::SmallLu<T> lu;
    if (!factor_stage_matrix(sys, h, lu)) return false;
    step_rows_of_size(sys, lu, x, h, phi);
    return true;
  }
  // step() of x, and of `count` (at most kMaxStates) more states without the input term, through
  // one factorisation: how x's response to a change of its start moves (x is affine in its start
  // with A and c held), for a caller that wants both, at the cost of one assembly and one
  // factorisation a step. Each gets the bits a step() of it alone gives.
  template <class R>
  static bool step_with_responses(const HeatBalance<T>& sys, T* x, T* const* responses, int count, const R& h,
                                  internal::SmallLu<T>& lu) {
    if (!factor_stage_matrix(sys, h, lu)) return false;
    T* columns[kMaxStates + 1] = {x};
    for (int r = 0; r < count; ++r) columns[1 + r] = responses[r];
    advance<kMaxStates + 1>(sys, lu, columns, 1 + count, 1, h);
    return true;
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

  // x (if given) stepped, and phi's columns: the unit vectors stepped without the input term.
  template <class R>
  static void step_and_columns(const HeatBalance<T>& sys, const internal::SmallLu<T>& lu, T* x, const R& h,
                               T (&phi)[kMaxStates][kMaxStates]) {
    const int n = sys.n;
    T unit[kMaxStates][kMaxStates];
    T* columns[kMaxStates + 1];
    int count = 0;
    if (x) columns[count++] = x;
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) unit[j][i] = T(i == j ? 1 : 0);
      columns[count++] = unit[j];
    }
    advance<kMaxStates + 1>(sys, lu, columns, count, x ? 1 : 0, h);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) phi[i][j] = unit[j][i];
  }

  // step_rows<N>() for N = sys.n (1 .. kMaxStates).
  template <class R, int N = 1>
  static void step_rows_of_size(const HeatBalance<T>& sys, const internal::SmallLu<T>& lu, T* x, const R& h,
                                T (&phi)[kMaxStates][kMaxStates]) {
    if constexpr (N < kMaxStates) {
      if (sys.n != N) return step_rows_of_size<R, N + 1>(sys, lu, x, h, phi);
    }
    step_rows<N>(sys, lu, x, h, phi);
  }

  // step_and_columns() of x and the N unit vectors, with N (= sys.n) a constant: the N + 1 states
  // held by row in one array, s[i][c] state c's entry i (the state first), so that the loops over
  // the states are innermost and of a constant length, which a compiler unrolls into vector
  // operations (two divisions at once, where the back substitution's divisions were most of the
  // step). Each state's arithmetic is advance()'s for it alone, in advance()'s order: the same bits
  // (Integrator.StepAndTransitionGiveTheBitsOfStepAndOfTransition holds it, for every size).
  template <int N, class R>
  static void step_rows(const HeatBalance<T>& sys, const internal::SmallLu<T>& lu, T* x, const R& h,
                        T (&phi)[kMaxStates][kMaxStates]) {
    constexpr int C = N + 1;
    // sys.derivative() of each state, the input term c in the first state's only.
    auto rates = [&](const T (&at)[N][C], T (&k)[N][C]) {
      for (int i = 0; i < N; ++i) {
        k[i][0] = sys.c[i];
        for (int c = 1; c < C; ++c) k[i][c] = T(0);
        for (int j = 0; j < N; ++j) {
          const T a = sys.a[i][j];
          for (int c = 0; c < C; ++c) k[i][c] += a * at[j][c];
        }
      }
    };
    T s[N][C];
    for (int i = 0; i < N; ++i) {
      s[i][0] = x[i];
      for (int j = 0; j < N; ++j) s[i][1 + j] = T(i == j ? 1 : 0);
    }
    // Stage 1: k1 = A (x + gamma h k1) + c.
    T k1[N][C];
    rates(s, k1);
    lu.solve_rows(k1);
    // Stage 2: k2 = A (x + (1 - gamma) h k1 + gamma h k2) + c.
    T x1[N][C];
    const T w1 = T((1.0 - kGamma) * h);
    for (int i = 0; i < N; ++i)
      for (int c = 0; c < C; ++c) x1[i][c] = s[i][c] + w1 * k1[i][c];
    T k2[N][C];
    rates(x1, k2);
    lu.solve_rows(k2);
    // Stiffly accurate: the new state is the second stage's.
    const T w2 = T(kGamma * h);
    for (int i = 0; i < N; ++i) {
      x[i] = x1[i][0] + w2 * k2[i][0];
      for (int j = 0; j < N; ++j) phi[i][j] = x1[i][1 + j] + w2 * k2[i][1 + j];
    }
  }

  // The two stages, for `count` (at most Capacity) states at once: columns[0 .. with_input) with
  // the input term c, the rest without it (the homogeneous part, for transition() and the
  // responses). Each column's arithmetic is one column's alone in the same order, so it gets the
  // same bits however many are stepped beside it; they are interleaved stage by stage so that
  // the solves of independent columns overlap (SmallLu::solve_columns).
  template <int Capacity, class R>
  static void advance(const HeatBalance<T>& sys, const internal::SmallLu<T>& lu, T* const* columns, int count,
                      int with_input, const R& h) {
    const int n = sys.n;
    auto rate = [&](int i, const T* at, bool input) {  // sys.derivative(), with or without c
      T p = input ? sys.c[i] : T(0);
      for (int j = 0; j < n; ++j) p += sys.a[i][j] * at[j];
      return p;
    };
    // Stage 1: k1 = A (x + gamma h k1) + c.
    T k1[Capacity][kMaxStates];
    T* k1_columns[Capacity] = {};
    for (int c = 0; c < count; ++c) {
      k1_columns[c] = k1[c];
      for (int i = 0; i < n; ++i) k1[c][i] = rate(i, columns[c], c < with_input);
    }
    lu.solve_columns(k1_columns, count);
    // Stage 2: k2 = A (x + (1 - gamma) h k1 + gamma h k2) + c.
    T x1[Capacity][kMaxStates];
    const T w1 = T((1.0 - kGamma) * h);
    for (int c = 0; c < count; ++c)
      for (int i = 0; i < n; ++i) x1[c][i] = columns[c][i] + w1 * k1[c][i];
    T k2[Capacity][kMaxStates];
    T* k2_columns[Capacity] = {};
    for (int c = 0; c < count; ++c) {
      k2_columns[c] = k2[c];
      for (int i = 0; i < n; ++i) k2[c][i] = rate(i, x1[c], c < with_input);
    }
    lu.solve_columns(k2_columns, count);
    // Stiffly accurate: the new state is the second stage's.
    const T w2 = T(kGamma * h);
    for (int c = 0; c < count; ++c)
      for (int i = 0; i < n; ++i) columns[c][i] = x1[c][i] + w2 * k2[c][i];
  }
};

}  // namespace lptn
