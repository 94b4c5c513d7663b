#include "trainer/fleet/cooling_factor_fit.hpp"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <algorithm>

#include "trainer/lm/correlation_time.hpp"
#include "trainer/calibrate/grid_residuals.hpp"
#include "trainer/model/cooling_factor.hpp"
#include "trainer/model/initial_offsets.hpp"

namespace lptn::fleet {
namespace {

// One cycle's grid residuals, uncompressed: three columns (ln factor, two offsets) leave the
// Jacobian small even for a long cycle (a few MB for hours of 10 Hz data).
class CycleCooling final : public ceres::CostFunction {
 public:
  CycleCooling(const Model<double>& model, const ParamVector<double>& params, const data::Cycle& cycle)
      : model_(model), params_(params), cycle_(cycle) {
    measured_ = calibrate::count_grid_residuals(cycle);
    set_num_residuals(static_cast<int>(measured_));
    mutable_parameter_block_sizes()->push_back(1);
    mutable_parameter_block_sizes()->push_back(2);
  }
  std::size_t measured() const { return measured_; }

  bool Evaluate(double const* const* blocks, double* residuals, double** jacobians) const override {
    const double log_factor = blocks[0][0];
    const double* offset = blocks[1];
    std::size_t row = 0;
    if (jacobians == nullptr || (jacobians[0] == nullptr && jacobians[1] == nullptr)) {
      return calibrate::for_each_grid_residual(model_, with_cooling_factor(params_, std::exp(log_factor)),
                                    cycle_, InitialOffsets<double>{offset[0], offset[1]},
                                    [&](const double& e) { residuals[row++] = e; });
    }
    using Jet = ceres::Jet<double, 3>;
    ParamVector<Jet> p;
    for (int i = 0; i < kNumParams; ++i) p[i] = Jet(params_[i]);
    const Jet factor = exp(Jet(log_factor, 0));
    return calibrate::for_each_grid_residual(model_, with_cooling_factor(p, factor), cycle_,
                                  InitialOffsets<Jet>{Jet(offset[0], 1), Jet(offset[1], 2)}, [&](const Jet& e) {
                                    residuals[row] = e.a;
                                    if (jacobians[0] != nullptr) jacobians[0][row] = e.v[0];
                                    if (jacobians[1] != nullptr) {
                                      jacobians[1][2 * row] = e.v[1];
                                      jacobians[1][2 * row + 1] = e.v[2];
                                    }
                                    ++row;
                                  });
  }

 private:
  const Model<double>& model_;
  const ParamVector<double>& params_;
  const data::Cycle& cycle_;
  std::size_t measured_ = 0;
};

// The factor's bounds: a motor cooling a fifth of nominal, or five times it, is no longer a
// question of calibration.
constexpr double kMinLogFactor = -1.6, kMaxLogFactor = 1.6;

}  // namespace

CoolingFactorFit fit_cooling_factor(const Model<double>& model, const ParamVector<double>& params,
                                    const data::Dataset& dataset, const std::vector<std::size_t>& cycles,
                                    int threads) {
  CoolingFactorFit out;
  double log_factor = 0;
  std::vector<std::array<double, 2>> offsets(cycles.size());
  for (std::size_t i = 0; i < cycles.size(); ++i) {
    const InitialOffsets<double> o = estimate_initial_offsets(model, params, dataset.cycles[cycles[i]]);
    offsets[i] = {o.stator_core, o.rotor_core};
  }
  ceres::Problem problem;  // owns the cost functions
  std::vector<double*> offset_blocks;
  for (std::size_t i = 0; i < cycles.size(); ++i) {
    auto* cost = new CycleCooling(model, params, dataset.cycles[cycles[i]]);
    if (cost->measured() == 0) {
      delete cost;
      continue;
    }
    out.residuals += cost->measured();
    problem.AddResidualBlock(cost, nullptr, &log_factor, offsets[i].data());
    offset_blocks.push_back(offsets[i].data());
    for (int j = 0; j < 2; ++j) {
      problem.SetParameterLowerBound(offsets[i].data(), j, -kInitialOffsetBoundK);
      problem.SetParameterUpperBound(offsets[i].data(), j, kInitialOffsetBoundK);
    }
  }
  if (out.residuals == 0) throw std::runtime_error("no cycle of the motor has a stator or rotor measurement");
  problem.SetParameterLowerBound(&log_factor, 0, kMinLogFactor);
  problem.SetParameterUpperBound(&log_factor, 0, kMaxLogFactor);

  ceres::Solver::Options options;
  options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  options.max_num_iterations = 50;
  options.function_tolerance = 1e-10;
  options.parameter_tolerance = 1e-10;
  options.num_threads = threads;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  out.iterations = static_cast<int>(summary.iterations.size()) - 1;
  out.factor = std::exp(log_factor);
  out.rmse_k = std::sqrt(2.0 * summary.final_cost / static_cast<double>(out.residuals));
  for (const auto& o : offsets) out.offsets.push_back({o[0], o[1]});

  // Standard error: J^T J over (ln factor, every offset), its inverse's first entry (the offsets
  // profiled out), s^2 from the residuals, times their correlation time.
  ceres::CRSMatrix jacobian;
  std::vector<double> residuals;
  double cost = 0;
  ceres::Problem::EvaluateOptions evaluate;
  evaluate.parameter_blocks.push_back(&log_factor);
  for (double* b : offset_blocks) evaluate.parameter_blocks.push_back(b);
  evaluate.num_threads = threads;
  problem.Evaluate(evaluate, &cost, &residuals, nullptr, &jacobian);
  Eigen::MatrixXd jtj = Eigen::MatrixXd::Zero(jacobian.num_cols, jacobian.num_cols);
  for (int r = 0; r < jacobian.num_rows; ++r) {
    const auto begin = static_cast<std::size_t>(jacobian.rows[static_cast<std::size_t>(r)]);
    const auto end = static_cast<std::size_t>(jacobian.rows[static_cast<std::size_t>(r) + 1]);
    for (std::size_t a = begin; a < end; ++a)
      for (std::size_t b = begin; b < end; ++b)
        jtj(jacobian.cols[a], jacobian.cols[b]) += jacobian.values[a] * jacobian.values[b];
  }
  // Residual series per block and sensor, demeaned, for the correlation time (fit_lm's rule).
  std::vector<std::vector<double>> series[2];  // the stator's, the rotor's
  std::size_t row = 0;
  for (std::size_t i = 0; i < cycles.size(); ++i) {
    const data::Cycle& cycle = dataset.cycles[cycles[i]];
    std::vector<double> stator, rotor;
    for (std::size_t k = 1; k < cycle.steps; ++k) {
      if (!std::isnan(cycle.at(data::Channel::stator_winding_c, k))) stator.push_back(residuals[row++]);
      if (!std::isnan(cycle.at(data::Channel::rotor_c, k))) rotor.push_back(residuals[row++]);
    }
    std::vector<double>* sensor[2] = {&stator, &rotor};
    for (int s = 0; s < 2; ++s) {
      if (sensor[s]->empty()) continue;
      double mean = 0;
      for (double e : *sensor[s]) mean += e;
      mean /= static_cast<double>(sensor[s]->size());
      for (double& e : *sensor[s]) e -= mean;
      series[s].push_back(std::move(*sensor[s]));
    }
  }
  out.correlation_time = std::max(lm::correlation_time(series[0]), lm::correlation_time(series[1]));
  const double dof = std::max(1.0, static_cast<double>(out.residuals) - static_cast<double>(jacobian.num_cols));
  const double s2 = 2.0 * cost / dof * out.correlation_time;
  const Eigen::MatrixXd cov = s2 * jtj.completeOrthogonalDecomposition().pseudoInverse();
  out.log_std_error = std::sqrt(std::max(0.0, cov(0, 0)));
  return out;
}

}  // namespace lptn::fleet
