// The network of one step as a linear system, built term by term.
//
// Every part of the model (the paper's four nodes, each effect) contributes heat paths, losses and
// couplings in power units; finish() divides by the capacitances. The result is
//     dx/dt = A x + c
// with A and c held over the step (inputs are sampled once per step). The system is linear in the
// state because the only state-dependent losses, the copper losses, are affine in temperature.
#pragma once

#include "lptn/scalar.hpp"

namespace lptn {

inline constexpr int kMaxStates = 8;

// Node numbering of the paper: 1 stator winding, 2 stator core, 3 rotor winding, 4 rotor core.
enum Node : int { kStatorWinding = 0, kStatorCore = 1, kRotorWinding = 2, kRotorCore = 3, kNumNodes = 4 };

template <class T>
struct HeatBalance {
  int n = kNumNodes;               // active states: the four nodes, then effects' extra states
  T a[kMaxStates][kMaxStates]{};   // before finish(): W/K; after: 1/s
  T c[kMaxStates]{};               // before finish(): W;   after: K/s
  T capacitance[kMaxStates]{};     // J/K; 1 for states that carry a rate directly (sensor models)

  // Clears the active states' block: everything reads only rows and columns 0..n-1.
  void reset(int states) {
    n = states;
    for (int i = 0; i < n; ++i) {
      c[i] = T(0);
      capacitance[i] = T(1);
      for (int j = 0; j < n; ++j) a[i][j] = T(0);
    }
  }

  // A conductance g (W/K) between two states: heat flows from the hotter to the colder.
  void path(int i, int j, const T& g) {
    a[i][i] -= g;
    a[i][j] += g;
    a[j][j] -= g;
    a[j][i] += g;
  }
  // A conductance g (W/K) from state i to a fixed temperature (the cooling air).
  template <class R>
  void to_fixed(int i, const T& g, const R& temperature_c) {
    a[i][i] -= g;
    c[i] += g * temperature_c;
  }
  // A loss P (W) deposited in state i.
  void heat(int i, const T& p) { c[i] += p; }
  // A loss that grows with the state's own temperature, P = p20 (1 + alpha (x_i - 20)), as copper
  // losses do through the winding resistance. Kept implicit in A, not lagged by a step.
  template <class R>
  void heat_affine(int i, const T& p20, const R& alpha_per_k) {
    a[i][i] += p20 * alpha_per_k;
    c[i] += p20 * (R(1) - R(20) * alpha_per_k);
  }
  // A one-way coupling: the rate of state i gains k x_j (units of a[i][i]). For sensor models and
  // air heated upstream, which move heat or signal in one direction only.
  void coupling(int i, int j, const T& k) { a[i][j] += k; }

  // dx_i/dt at state x: net power into the state (W) before finish(), its rate (K/s) after.
  T derivative(int i, const T* x) const {
    T p = c[i];
    for (int j = 0; j < n; ++j) p += a[i][j] * x[j];
    return p;
  }

  void finish() {
    for (int i = 0; i < n; ++i) finish_row(i);
  }
  // This network as `raw` (not yet finished) would be after finish(): the active block copied
  // and finished row by row, the rest left alone.
  void finish_from(const HeatBalance& raw) {
    n = raw.n;
    for (int i = 0; i < n; ++i) {
      capacitance[i] = raw.capacitance[i];
      c[i] = raw.c[i];
      for (int j = 0; j < n; ++j) a[i][j] = raw.a[i][j];
      finish_row(i);
    }
  }
  // finish() of row i alone: rows are finished independently (a caller that needs some rows'
  // rates only finishes those).
  void finish_row(int i) {
    const T inv = T(1) / capacitance[i];
    c[i] *= inv;
    for (int j = 0; j < n; ++j) a[i][j] *= inv;
  }
};

}  // namespace lptn
