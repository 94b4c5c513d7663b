#include "trainer/model/initial_offsets.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace lptn::model {
namespace {

// Model minus measurement at every measured grid point of the window (r0, offsets zero), in a
// fixed order, and how each moves with a unit stator-core offset (a) and rotor-core offset (b):
// one run, the two responses stepped beside the state through each step's factorisation.
struct Window {
  std::vector<double> r0, a, b;
};

Window window_residuals(const Model<double>& model, const ParamVector<double>& params, const data::Cycle& cycle,
                        std::size_t steps, const PreparedCycle* prepared) {
  Window w;
  double x[kMaxStates], along_s[kMaxStates], along_t[kMaxStates];
  initial_state_for(model, cycle, x);
  {  // the responses start as what a unit offset adds to the start
    double shifted[kMaxStates];
    initial_state_for(model, cycle, shifted, InitialOffsets<double>{1.0, 0.0});
    for (int i = 0; i < kMaxStates; ++i) along_s[i] = shifted[i] - x[i];
    initial_state_for(model, cycle, shifted, InitialOffsets<double>{0.0, 1.0});
    for (int i = 0; i < kMaxStates; ++i) along_t[i] = shifted[i] - x[i];
  }
  double* responses[2] = {along_s, along_t};
  typename Model<double>::template StepWorkspace<double> work;
  const std::size_t n = std::min(cycle.steps, steps);
  for (std::size_t k = 0; k + 1 < n; ++k) {
    // Grid step 0 starts at the measurement by construction; step k's result is grid k + 1's.
    if (prepared)
      model.step_with_responses(x, (*prepared)[k], params.data(), cycle.dt_s, work, responses, 2);
    else
      model.step_with_responses(x, model.prepare(inputs_at(cycle, k)), params.data(), cycle.dt_s, work, responses, 2);
    const float ys = cycle.at(data::Channel::stator_winding_c, k + 1);
    const float yr = cycle.at(data::Channel::rotor_c, k + 1);
    if (!std::isnan(ys)) {
      w.r0.push_back(model.stator_sensor(x) - ys);
      w.a.push_back(model.stator_sensor(along_s));
      w.b.push_back(model.stator_sensor(along_t));
    }
    if (!std::isnan(yr)) {
      w.r0.push_back(model.rotor_sensor(x) - yr);
      w.a.push_back(model.rotor_sensor(along_s));
      w.b.push_back(model.rotor_sensor(along_t));
    }
  }
  return w;
}

// The cost |r0 + s a + t b|^2 of a candidate, from the normal equations' sums.
struct Quadratic {
  double aa = 0, ab = 0, bb = 0, ar = 0, br = 0, rr = 0;
  double cost(double s, double t) const {
    return rr + 2 * (s * ar + t * br) + s * s * aa + 2 * s * t * ab + t * t * bb;
  }
};

// The minimizer along one offset with the other held at `other` (0 where that offset does not
// change the outputs), clamped to the box.
double along(double self_self, double self_other, double self_r, double other) {
  if (self_self <= 0) return 0.0;
  return std::clamp(-(self_r + self_other * other) / self_self, -kInitialOffsetBoundK, kInitialOffsetBoundK);
}

}  // namespace

InitialOffsets<double> estimate_initial_offsets(const Model<double>& model, const ParamVector<double>& params,
                                               const data::Cycle& cycle, double window_s,
                                               const PreparedCycle* prepared) {
  const auto steps = static_cast<std::size_t>(std::max(2.0, window_s / cycle.dt_s));
  const Window w = window_residuals(model, params, cycle, steps, prepared);
  const std::vector<double>& r0 = w.r0;
  if (r0.empty()) return {};
  Quadratic q;
  for (std::size_t i = 0; i < r0.size(); ++i) {
    const double a = w.a[i], b = w.b[i];
    q.aa += a * a;
    q.ab += a * b;
    q.bb += b * b;
    q.ar += a * r0[i];
    q.br += b * r0[i];
    q.rr += r0[i] * r0[i];
  }
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

}  // namespace lptn::model
