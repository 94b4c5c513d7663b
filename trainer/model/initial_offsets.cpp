#include "trainer/model/initial_offsets.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace lptn::model {
namespace {

// The cost |r0 + s a + t b|^2 of a candidate, from the normal equations' sums: r0 the model minus
// the measurement at every measured grid point of the window (offsets zero), a and b how each
// moves with a unit stator-core offset (s) and rotor-core offset (t).
struct Quadratic {
  double aa = 0, ab = 0, bb = 0, ar = 0, br = 0, rr = 0;
  std::size_t samples = 0;
  void add(double r0, double a, double b) {
    aa += a * a;
    ab += a * b;
    bb += b * b;
    ar += a * r0;
    br += b * r0;
    rr += r0 * r0;
    ++samples;
  }
  double cost(double s, double t) const {
    return rr + 2 * (s * ar + t * br) + s * s * aa + 2 * s * t * ab + t * t * bb;
  }
};

// The window's sums for L parameter sets (L = 1: doubles; else lanes, each lane a double's bits):
// one run, the two responses stepped beside the state through each step's factorisation; the
// stator sensor's point before the rotor's at each grid step, the order the sums are taken in.
template <int L>
void window_sums(const Model<double>& model, const ParamVector<double>* params, const data::Cycle& cycle,
                 std::size_t steps, const PreparedCycle* prepared, Quadratic* out) {
  using T = std::conditional_t<L == 1, double, Lanes<L>>;
  T x[kMaxStates], along_s[kMaxStates], along_t[kMaxStates];
  initial_state_for(model, cycle, x);
  {  // the responses start as what a unit offset adds to the start
    double start[kMaxStates], shifted[kMaxStates];
    initial_state_for(model, cycle, start);
    initial_state_for(model, cycle, shifted, InitialOffsets<double>{1.0, 0.0});
    for (int i = 0; i < kMaxStates; ++i) along_s[i] = T(shifted[i] - start[i]);
    initial_state_for(model, cycle, shifted, InitialOffsets<double>{0.0, 1.0});
    for (int i = 0; i < kMaxStates; ++i) along_t[i] = T(shifted[i] - start[i]);
  }
  T* responses[2] = {along_s, along_t};
  auto lane = [](const T& v, int l) {
    if constexpr (L == 1) {
      (void)l;
      return v;
    } else {
      return v.lane(l);
    }
  };
  auto add = [&](const T& model_reading, const T& a, const T& b, float y) {
    for (int l = 0; l < L; ++l) out[l].add(lane(model_reading, l) - y, lane(a, l), lane(b, l));
  };
  SetStepper<L> stepper(model, params);
  Model<double>::PreparedInputs computed{};
  const std::size_t n = std::min(cycle.steps, steps);
  for (std::size_t k = 0; k + 1 < n; ++k) {
    // Grid step 0 starts at the measurement by construction; step k's result is grid k + 1's.
    const Model<double>::PreparedInputs& in = prepared ? (*prepared)[k] : (computed = model.prepare(inputs_at(cycle, k)));
    stepper.step(x, in, cycle.dt_s, responses, 2);
    const float ys = cycle.at(data::Channel::stator_winding_c, k + 1);
    const float yr = cycle.at(data::Channel::rotor_c, k + 1);
    if (!std::isnan(ys)) add(model.stator_sensor(x), model.stator_sensor(along_s), model.stator_sensor(along_t), ys);
    if (!std::isnan(yr)) add(model.rotor_sensor(x), model.rotor_sensor(along_s), model.rotor_sensor(along_t), yr);
  }
}

// The minimizer along one offset with the other held at `other` (0 where that offset does not
// change the outputs), clamped to the box.
double along(double self_self, double self_other, double self_r, double other) {
  if (self_self <= 0) return 0.0;
  return std::clamp(-(self_r + self_other * other) / self_self, -kInitialOffsetBoundK, kInitialOffsetBoundK);
}

}  // namespace

namespace {

// The bounded least-squares offsets from the window's sums.
InitialOffsets<double> offsets_from(const Quadratic& q) {
  if (q.samples == 0) return {};
  // An offset that moves no output stays 0 (as a damped solver leaves a direction without
  // information); so does the other's share of a pair that cannot be told apart.
  const double det = q.aa * q.bb - q.ab * q.ab;
  const bool both = q.aa > 0 && q.bb > 0 && det > 1e-12 * q.aa * q.bb;
  if (both) {
    const double s = (q.ab * q.br - q.bb * q.ar) / det, t = (q.ab * q.ar - q.aa * q.br) / det;
    if (std::abs(s) <= kInitialOffsetBoundK && std::abs(t) <= kInitialOffsetBoundK) return {s, t};
  }
  // The unconstrained minimum lies outside the box (or one direction is empty): the bounded
  // minimum lies on an edge, each edge's best point is a one-dimensional clamp, and the best of
  // them is the answer (the cost is convex, so this is exact).
  std::array<std::array<double, 2>, 6> candidates{};
  std::size_t n = 0;
  candidates[n++] = {along(q.aa, q.ab, q.ar, 0.0), 0.0};
  candidates[n++] = {0.0, along(q.bb, q.ab, q.br, 0.0)};
  if (both) {
    for (const double edge : {-kInitialOffsetBoundK, kInitialOffsetBoundK}) {
      candidates[n++] = {edge, along(q.bb, q.ab, q.br, edge)};
      candidates[n++] = {along(q.aa, q.ab, q.ar, edge), edge};
    }
  }
  std::array<double, 2> best = candidates[0];
  for (std::size_t i = 1; i < n; ++i)
    if (q.cost(candidates[i][0], candidates[i][1]) < q.cost(best[0], best[1])) best = candidates[i];
  return {best[0], best[1]};
}

std::size_t window_steps(const data::Cycle& cycle, double window_s) {
  return static_cast<std::size_t>(std::max(2.0, window_s / cycle.dt_s));
}

}  // namespace

InitialOffsets<double> estimate_initial_offsets(const Model<double>& model, const ParamVector<double>& params,
                                               const data::Cycle& cycle, double window_s,
                                               const PreparedCycle* prepared) {
  Quadratic q;
  window_sums<1>(model, &params, cycle, window_steps(cycle, window_s), prepared, &q);
  return offsets_from(q);
}

template <int L>
void estimate_initial_offsets_lanes(const Model<double>& model, const ParamVector<double>* params,
                                    const data::Cycle& cycle, InitialOffsets<double>* out, double window_s,
                                    const PreparedCycle* prepared) {
  Quadratic q[L];
  const std::size_t steps = window_steps(cycle, window_s);
  if constexpr (L == 4)
    run_on_widest_lanes([&] { window_sums<4>(model, params, cycle, steps, prepared, q); });
  else
    window_sums<L>(model, params, cycle, steps, prepared, q);
  for (int l = 0; l < L; ++l) out[l] = offsets_from(q[l]);
}
template void estimate_initial_offsets_lanes<2>(const Model<double>&, const ParamVector<double>*, const data::Cycle&,
                                                InitialOffsets<double>*, double, const PreparedCycle*);
template void estimate_initial_offsets_lanes<4>(const Model<double>&, const ParamVector<double>*, const data::Cycle&,
                                                InitialOffsets<double>*, double, const PreparedCycle*);

}  // namespace lptn::model
