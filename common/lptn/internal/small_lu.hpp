// LU factorisation with partial pivoting for the integrator's n x n stage matrix (n <= kMaxStates).
// Fixed-capacity arrays, no heap, no exceptions; works for float, double and Jets (pivoting looks
// at the value part only).
#pragma once

#include "lptn/heat_balance.hpp"
#include "lptn/scalar.hpp"

namespace lptn::internal {

template <class T>
struct SmallLu {
  int n = 0;
  T lu[kMaxStates][kMaxStates]{};
  int swap[kMaxStates]{};  // step k exchanged rows k and swap[k]

  // Factorises m (rows/cols 0..n-1). Returns false if a pivot is exactly zero, which the
  // integrator's matrix I - gamma h A cannot produce for a passive network (it is diagonally
  // dominant); the caller then keeps the state unchanged rather than divide by zero.
  bool factor(const T (&m)[kMaxStates][kMaxStates], int size) {
    for (int i = 0; i < size; ++i)
      for (int j = 0; j < size; ++j) lu[i][j] = m[i][j];
    return factor_in_place(size);
  }

  // Factorises the matrix already written into lu (rows/cols 0..size-1), as factor() does. For
  // lanes, false also where the lanes would pivot on different rows (lanes_pivot).
  bool factor_in_place(int size) {
    using std::abs;
    n = size;
    for (int k = 0; k < n; ++k) {
      int p = k;
      if constexpr (kIsLanes<T>) {
        if (!lanes_pivot(k, p)) return false;
      } else {
        double best = abs(value_of(lu[k][k]));
        for (int i = k + 1; i < n; ++i) {
          const double v = abs(value_of(lu[i][k]));
          if (v > best) {
            best = v;
            p = i;
          }
        }
        if (best == 0.0) return false;
      }
      swap[k] = p;
      if (p != k) {
        for (int j = 0; j < n; ++j) {
          T t = lu[k][j];
          lu[k][j] = lu[p][j];
          lu[p][j] = t;
        }
      }
      const T inv = T(1) / lu[k][k];
      for (int i = k + 1; i < n; ++i) {
        lu[i][k] *= inv;
        for (int j = k + 1; j < n; ++j) lu[i][j] -= lu[i][k] * lu[k][j];
      }
    }
    return true;
  }

  // Lanes (lanes.hpp): the pivot each lane alone would take (the same search as above, lane by
  // lane). False where the lanes do not all take the same row, or any lane's pivot is zero: the
  // caller then steps each lane as a double (the lanes cannot exchange different rows), so every
  // lane gets a double's bits whatever its neighbours do.
  bool lanes_pivot(int k, int& p) const {
    using std::abs;
    p = -1;
    for (int l = 0; l < T::kLanes; ++l) {
      int lane_p = k;
      double best = abs(lu[k][k].lane(l));
      for (int i = k + 1; i < n; ++i) {
        const double v = abs(lu[i][k].lane(l));
        if (v > best) {
          best = v;
          lane_p = i;
        }
      }
      if (best == 0.0 || (p >= 0 && lane_p != p)) return false;
      p = lane_p;
    }
    return true;
  }

  // Solves (LU) x = b in place: the row exchanges in the order factoring made them (LAPACK's
  // getrs), then both substitutions on b itself. No temporary: with Jets, a temporary of
  // kMaxStates entries would be constructed (zeroed) on every call.
  void solve(T* b) const {
    T* const columns[1] = {b};
    solve_columns(columns, 1);
  }
  // solve() of C right-hand sides held by row, b[i][c] row i of side c, for a factorisation of
  // size N (= n): each side with exactly solve()'s arithmetic in solve()'s order (so each gets
  // solve()'s bits), the sides innermost, in loops of constant length (Sdirk2::step_rows).
  template <int N, int C>
  void solve_rows(T (&b)[N][C]) const {
    // One row is never exchanged (factor_in_place searches rows k+1..n-1 for a pivot). Said here,
    // not only known: for N = 1 g++ -O3 cannot see that swap[0] is 0 and reports the exchange as
    // an access out of b's bounds (-Warray-bounds, an error in the ci preset).
    if constexpr (N > 1)
      for (int k = 0; k < N; ++k)
        if (swap[k] != k)
          for (int c = 0; c < C; ++c) {
            T t = b[k][c];
            b[k][c] = b[swap[k]][c];
            b[swap[k]][c] = t;
          }
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < i; ++j) {
        const T l = lu[i][j];
        for (int c = 0; c < C; ++c) b[i][c] -= l * b[j][c];
      }
    for (int i = N - 1; i >= 0; --i) {
      for (int j = i + 1; j < N; ++j) {
        const T u = lu[i][j];
        for (int c = 0; c < C; ++c) b[i][c] -= u * b[j][c];
      }
      const T d = lu[i][i];
      for (int c = 0; c < C; ++c) b[i][c] /= d;
    }
  }
  // solve() of `count` right-hand sides, each with exactly solve()'s arithmetic in solve()'s order
  // (so each gives solve()'s bits), interleaved row by row: the back substitution's divisions of
  // different columns are independent and overlap in the pipeline, where one column's wait for
  // each other in turn.
  void solve_columns(T* const* b, int count) const {
    for (int k = 0; k < n; ++k)
      if (swap[k] != k)
        for (int c = 0; c < count; ++c) {
          T t = b[c][k];
          b[c][k] = b[c][swap[k]];
          b[c][swap[k]] = t;
        }
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < count; ++c)
        for (int j = 0; j < i; ++j) b[c][i] -= lu[i][j] * b[c][j];
    for (int i = n - 1; i >= 0; --i)
      for (int c = 0; c < count; ++c) {
        for (int j = i + 1; j < n; ++j) b[c][i] -= lu[i][j] * b[c][j];
        b[c][i] /= lu[i][i];
      }
  }
};

}  // namespace lptn::internal
