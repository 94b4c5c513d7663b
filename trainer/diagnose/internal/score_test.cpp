#include "trainer/diagnose/internal/score_test.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>


namespace lptn::diagnose::internal {
namespace {

// The effect's parameters searched linearly: their neutral value is often 0 (or outside the
// bounds), where a log coordinate does not exist. The statistic does not depend on the scale.
FreeParameters linear_in_effect(const MotorFile& motor, int effect) {
  FreeParameters free = FreeParameters::from_motor(motor);
  for (std::size_t j = 0; j < free.size(); ++j)
    if (effect_of_param(free.index[j]) == effect) free.log_scale[j] = false;
  return free;
}

// Whether the Gauss-Newton step `step` moves at least one of the effect's parameters from its
// evaluation point into its bounds. A step that would need, say, a negative loss only shows that
// the residuals point away from the effect: it cannot take that step, and its score is nil.
bool step_feasible(const FreeParameters& free, const ParamVector<double>& at, const Eigen::VectorXd& step, int effect) {
  for (std::size_t j = 0; j < free.size(); ++j) {
    if (effect_of_param(free.index[j]) != effect) continue;
    const double v = at[free.index[j]], s = step(static_cast<Eigen::Index>(j));
    if ((v > free.min[j] || s > 0) && (v < free.max[j] || s < 0)) return true;
  }
  return false;
}

}  // namespace

ParamVector<double> neutral_point(const ParamVector<double>& calibrated, int effect) {
  ParamVector<double> at = calibrated;
  bool first = true;
  for (int i = 0; i < kNumParams; ++i) {
    if (effect_of_param(i) != effect) continue;
    const double override_at = EffectLibrary::kScoreAt[static_cast<std::size_t>(effect)];
    at[i] = first && !std::isnan(override_at) ? override_at : param_spec(i).neutral;
    first = false;
  }
  return at;
}

Score score_test(const MotorFile& with_effect, int effect, const LmReport& baseline, const data::Dataset& dataset,
                 const std::vector<std::size_t>& train, int threads) {
  const FreeParameters free = linear_in_effect(with_effect, effect);
  const ParamVector<double> at = neutral_point(baseline.values, effect);
  const NormalEquations ne =
      normal_equations(with_effect.model(), free, at, dataset, train, baseline.offsets, threads);
  const auto m = static_cast<Eigen::Index>(ne.columns);
  const Eigen::Map<const Eigen::MatrixXd> jtj(ne.jtj.data(), m, m);
  const Eigen::Map<const Eigen::VectorXd> g(ne.jtr.data(), m);
  // Columns in W/K, s, log units and kelvin differ by decades: equilibrate before solving, so
  // that the rank decision sees the data's information and not the units.
  Eigen::VectorXd d = jtj.diagonal().cwiseSqrt().cwiseInverse();
  d = d.unaryExpr([](double x) { return std::isfinite(x) ? x : 0.0; });
  const Eigen::MatrixXd scaled = d.asDiagonal() * jtj * d.asDiagonal();
  const Eigen::VectorXd delta = d.asDiagonal() * scaled.completeOrthogonalDecomposition().solve(d.asDiagonal() * g);

  Score out;
  out.rss_k2 = ne.rss;
  out.residuals = ne.residuals;
  out.predicted = baseline.values;
  if (!step_feasible(free, at, -delta, effect)) return out;
  out.feasible = true;
  // The step's end for the effect's parameters (linear coordinates, see linear_in_effect), in bounds.
  for (std::size_t j = 0; j < free.size(); ++j) {
    const int i = free.index[j];
    if (effect_of_param(i) == effect)
      out.predicted[i] = std::clamp(at[i] - delta(static_cast<Eigen::Index>(j)), free.min[j], free.max[j]);
  }
  out.reduction_k2 = std::max(0.0, g.dot(delta));
  std::size_t fitted_before = 0;  // the baseline's free parameters: all but the effect's
  for (int i : free.index) fitted_before += effect_of_param(i) != effect;
  const double dof = std::max(1.0, static_cast<double>(baseline.residuals) - static_cast<double>(fitted_before));
  const double s2 = 2.0 * baseline.final_cost / dof;
  out.statistic = out.reduction_k2 / (s2 * baseline.correlation_time);
  return out;
}

}  // namespace lptn::diagnose::internal
