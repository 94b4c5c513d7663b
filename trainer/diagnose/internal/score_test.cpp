#include "trainer/diagnose/internal/score_test.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "trainer/model/motor_effects.hpp"


namespace lptn::diagnose::internal {
namespace {

// The effect's parameters searched linearly: their neutral value is often 0 (or outside the
// bounds), where a log coordinate does not exist. The statistic does not depend on the scale.
calibrate::FreeParameters linear_in_effect(const MotorFile& motor, int effect) {
  calibrate::FreeParameters free = calibrate::FreeParameters::from_motor(motor);
  for (std::size_t j = 0; j < free.size(); ++j)
    if (effect_of_param(free.index[j]) == effect) free.log_scale[j] = false;
  return free;
}

// Whether the Gauss-Newton step `step` moves at least one of the effect's parameters from its
// evaluation point into its bounds. A step that would need, say, a negative loss only shows that
// the residuals point away from the effect: it cannot take that step, and its score is nil. A
// parameter the step leaves where it is does not make it feasible: a term's exponent, which does
// nothing while the term's size is zero (its column of the Jacobian is zero, and so its step),
// made every term with an exponent "feasible" whichever way the data pulled its size.
bool step_feasible(const calibrate::FreeParameters& free, const ParamVector<double>& at, const Eigen::VectorXd& step, int effect) {
  for (std::size_t j = 0; j < free.size(); ++j) {
    if (effect_of_param(free.index[j]) != effect) continue;
    const double v = at[free.index[j]], s = step(static_cast<Eigen::Index>(j));
    if (s != 0 && (v > free.min[j] || s > 0) && (v < free.max[j] || s < 0)) return true;
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

namespace {

// The score from the normal equations of `free` (the baseline's free parameters and the effect's,
// then the cycles' offsets) at `at`, `jtj` and `g` in that column order.
Score score_from(const calibrate::FreeParameters& free, const ParamVector<double>& at, int effect, const lm::LmReport& baseline,
                 const Eigen::MatrixXd& jtj, const Eigen::VectorXd& g, double rss, std::size_t residuals) {
  // Columns in W/K, s, log units and kelvin differ by decades: equilibrate before solving, so
  // that the rank decision sees the data's information and not the units.
  Eigen::VectorXd d = jtj.diagonal().cwiseSqrt().cwiseInverse();
  d = d.unaryExpr([](double x) { return std::isfinite(x) ? x : 0.0; });
  const Eigen::MatrixXd scaled = d.asDiagonal() * jtj * d.asDiagonal();
  const Eigen::VectorXd delta = d.asDiagonal() * scaled.completeOrthogonalDecomposition().solve(d.asDiagonal() * g);

  Score out;
  out.rss_k2 = rss;
  out.residuals = residuals;
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

// Whether `effect` can be scored beside others from one Jacobian: at its neutral value it leaves
// the model as it was, and adds no state (a thermal mass's node would make every step of the
// joint simulation dearer than its own score test).
bool scored_jointly(int effect) {
  const auto e = static_cast<std::size_t>(effect);
  return EffectLibrary::kExtraStates[e] == 0 && std::isnan(EffectLibrary::kScoreAt[e]);
}

}  // namespace

Score score_test(const MotorFile& with_effect, int effect, const lm::LmReport& baseline, calibrate::DatasetRef dataset,
                 const std::vector<std::size_t>& train, int threads) {
  const calibrate::FreeParameters free = linear_in_effect(with_effect, effect);
  const ParamVector<double> at = neutral_point(baseline.values, effect);
  const lm::NormalEquations ne =
      lm::normal_equations(with_effect.model(), free, at, dataset, train, baseline.offsets, threads);
  const auto m = static_cast<Eigen::Index>(ne.columns);
  const Eigen::Map<const Eigen::MatrixXd> jtj(ne.jtj.data(), m, m);
  const Eigen::Map<const Eigen::VectorXd> g(ne.jtr.data(), m);
  return score_from(free, at, effect, baseline, jtj, g, ne.rss, ne.residuals);
}

std::vector<Score> score_tests(const MotorFile& motor, const std::vector<int>& effects, const lm::LmReport& baseline,
                               calibrate::DatasetRef dataset, const std::vector<std::size_t>& train, int threads,
                               const std::function<void(int)>& scoring) {
  std::vector<Score> out(effects.size());
  // Every effect that can be switched on at its neutral value beside the others: one simulation
  // with all of them, whose Jacobian holds each one's columns next to the baseline's. An effect at
  // its neutral value does nothing, so each one's normal equations are the joint ones restricted
  // to the baseline's columns and its own: its score test, for the cost of one.
  MotorFile all = motor;
  std::vector<std::size_t> joint;
  for (std::size_t k = 0; k < effects.size(); ++k)
    if (scored_jointly(effects[k])) {
      enable_effect(all, effects[k]);
      joint.push_back(k);
    }
  if (joint.size() < 2) joint.clear();
  for (std::size_t k = 0; k < effects.size(); ++k) {
    if (std::find(joint.begin(), joint.end(), k) != joint.end()) continue;
    MotorFile with = motor;
    enable_effect(with, effects[k]);
    if (scoring) scoring(effects[k]);
    out[k] = score_test(with, effects[k], baseline, dataset, train, threads);
  }
  if (joint.empty()) return out;

  calibrate::FreeParameters free_all = calibrate::FreeParameters::from_motor(all);
  ParamVector<double> at = baseline.values;
  for (std::size_t k : joint) {
    const int e = effects[k];
    const ParamVector<double> neutral = neutral_point(baseline.values, e);
    for (int i = 0; i < kNumParams; ++i)
      if (effect_of_param(i) == e) at[i] = neutral[i];
    for (std::size_t j = 0; j < free_all.size(); ++j)
      if (effect_of_param(free_all.index[j]) == e) free_all.log_scale[j] = false;
  }
  if (scoring) scoring(-1);
  const lm::NormalEquations ne = lm::normal_equations(all.model(), free_all, at, dataset, train, baseline.offsets, threads);
  const auto m_all = static_cast<Eigen::Index>(ne.columns);
  const Eigen::Map<const Eigen::MatrixXd> jtj_all(ne.jtj.data(), m_all, m_all);
  const Eigen::Map<const Eigen::VectorXd> g_all(ne.jtr.data(), m_all);
  const auto offsets = static_cast<Eigen::Index>(ne.columns - free_all.size());  // the cycles', after the parameters
  for (std::size_t k : joint) {
    const int e = effects[k];
    MotorFile with = motor;
    enable_effect(with, e);
    const calibrate::FreeParameters free = linear_in_effect(with, e);
    // The joint columns of this score test's parameters, in its own order, then the offsets.
    std::vector<Eigen::Index> columns;
    for (int i : free.index) {
      const auto it = std::find(free_all.index.begin(), free_all.index.end(), i);
      columns.push_back(static_cast<Eigen::Index>(it - free_all.index.begin()));
    }
    for (Eigen::Index o = 0; o < offsets; ++o) columns.push_back(static_cast<Eigen::Index>(free_all.size()) + o);
    const auto m = static_cast<Eigen::Index>(columns.size());
    Eigen::MatrixXd jtj(m, m);
    Eigen::VectorXd g(m);
    for (Eigen::Index a = 0; a < m; ++a) {
      g(a) = g_all(columns[static_cast<std::size_t>(a)]);
      for (Eigen::Index b = 0; b < m; ++b)
        jtj(a, b) = jtj_all(columns[static_cast<std::size_t>(a)], columns[static_cast<std::size_t>(b)]);
    }
    out[k] = score_from(free, neutral_point(baseline.values, e), e, baseline, jtj, g, ne.rss, ne.residuals);
  }
  return out;
}

}  // namespace lptn::diagnose::internal
