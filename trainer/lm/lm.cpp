#include "trainer/lm/lm.hpp"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <chrono>
#include <algorithm>
#include <array>
#include <utility>
#include <cmath>
#include <cstdint>
#include <memory>
#include <limits>
#include <stdexcept>
#include <string>

#include "trainer/lm/correlation_time.hpp"
#include "trainer/calibrate/grid_residuals.hpp"
#include "trainer/calibrate/sensor_noise.hpp"
#include "trainer/calibrate/shared_dataset.hpp"
#include "trainer/model/cooling_factor.hpp"
#include "trainer/model/initial_offsets.hpp"
#include "trainer/model/simulate.hpp"

namespace lptn::lm {
namespace {

constexpr int kOffsets = 2;  // per cycle: the stator core's and the rotor core's initial offset

// One cycle's residuals, as Ceres sees them: compressed to the cycle's contribution to the normal
// equations, so that memory does not grow with the data (a 200 h fleet dump has 14 million grid
// residuals; their Jacobian alone would need tens of gigabytes).
//
// With J (m x M) and r the cycle's grid residuals and their Jacobian in the M = free parameters +
// 2 offsets, and J^T J = V diag(lambda) V^T, the block presents M + 1 residuals:
//     r~_k = v_k^T J^T r / sqrt(lambda_k)   with Jacobian row sqrt(lambda_k) v_k^T   (lambda_k > 0)
//     e    = sqrt(r^T r - |r~|^2)           with Jacobian row 0
// Then |r~|^2 + e^2 = r^T r, J~^T J~ = J^T J and J~^T r~ = J^T r: the cost, the gradient and the
// Gauss-Newton model are those of the full residuals, so Levenberg-Marquardt takes the same steps,
// while J^T J, J^T r and r^T r are summed as the simulation runs and nothing per step is kept.
// Where Ceres asks for the cost only, the block presents (sqrt(r^T r), 0, ..., 0).
//
// The derivatives come from running the same simulation with ceres::Jet<double, N> (N >= M):
// they propagate exactly through assembly, LU and both SDIRK stages.
class CycleBlock : public ceres::CostFunction {
 public:
  // Grid points with a measurement (the residuals before compression).
  std::size_t measured() const { return measured_; }
  // The cycle's J^T J and J^T r as they are, before compression (columns: the free parameters,
  // then the two offsets), and r^T r; false where the model is not finite on the cycle.
  virtual bool normal_sums(const double* theta, const double* offset, Eigen::MatrixXd& jtj, Eigen::VectorXd& jtr,
                           double& rss) const = 0;

 protected:
  std::size_t measured_ = 0;
};

template <int N>
class CycleResiduals final : public CycleBlock {
 public:
  CycleResiduals(const Model<double>& model, const data::Cycle& cycle, const calibrate::FreeParameters& free,
                 const ParamVector<double>& fixed, std::size_t max_steps, double cooling,
                 const model::PreparedCycle* prepared)
      : model_(model), cycle_(cycle), free_(free), fixed_(fixed), max_steps_(std::min(max_steps, cycle.steps)),
        cooling_(cooling), prepared_(prepared) {
    measured_ = calibrate::count_grid_residuals(cycle, max_steps_);
    set_num_residuals(static_cast<int>(columns()) + 1);
    for (Jets& c : cache_) {
      c.at.assign(columns(), 0.0);
      c.residuals.assign(columns() + 1, 0.0);
      c.theta_jacobian.assign((columns() + 1) * free.size(), 0.0);
      c.offset_jacobian.assign((columns() + 1) * kOffsets, 0.0);
    }
    mutable_parameter_block_sizes()->push_back(static_cast<int>(free.size()));
    mutable_parameter_block_sizes()->push_back(kOffsets);
  }

  bool Evaluate(double const* const* blocks, double* residuals, double** jacobians) const override {
    const std::size_t nf = free_.size(), m = columns();
    const double* theta = blocks[0];
    const double* offset = blocks[1];
    std::fill(residuals, residuals + m + 1, 0.0);
    if (jacobians == nullptr || (jacobians[0] == nullptr && jacobians[1] == nullptr)) {
      // The cost alone: the line search's trial and then the step's candidate are the same point
      // (the line search asks for no derivatives: lm.cpp's options), simulated once.
      if (!plain_.valid || !std::equal(theta, theta + nf, plain_.at.begin()) ||
          !std::equal(offset, offset + kOffsets, plain_.at.begin() + static_cast<std::ptrdiff_t>(nf))) {
        ParamVector<double> p = fixed_;
        for (std::size_t j = 0; j < nf; ++j) p[free_.index[j]] = free_.to_physical(j, theta[j]);
        double rss = 0;
        plain_.ok = fill(model::with_cooling_factor(p, cooling_), model::InitialOffsets<double>{offset[0], offset[1]},
                         [&](const double& e) { rss += e * e; });
        plain_.rss = rss;
        plain_.at.assign(theta, theta + nf);
        plain_.at.insert(plain_.at.end(), offset, offset + kOffsets);
        plain_.valid = true;
      }
      residuals[0] = std::sqrt(plain_.rss);
      return plain_.ok;
    }
    // The derivatives at a point already differentiated are the ones found then: Ceres asks for
    // the Jacobian at a point more than once (10 requests for 5 points on a 48 h fit). The last
    // two points are kept: the covariance at the solution asks for the accepted point's, and with
    // the line search's cubic a rejected trial's had replaced it (a fifth of the 48 h baseline
    // refit's time); with its quadratic (below) no trial is differentiated, and two cost nothing.
    const Jets* jets = cached(theta, offset);
    if (jets == nullptr && (jets = evaluate_jets(theta, offset)) == nullptr) return false;
    std::copy(jets->residuals.begin(), jets->residuals.end(), residuals);
    if (jacobians[0] != nullptr) std::copy(jets->theta_jacobian.begin(), jets->theta_jacobian.end(), jacobians[0]);
    if (jacobians[1] != nullptr) std::copy(jets->offset_jacobian.begin(), jets->offset_jacobian.end(), jacobians[1]);
    return true;
  }

 private:
  // One differentiated point: where, its compressed residuals and both Jacobians.
  struct Jets {
    bool valid = false;
    std::vector<double> at, residuals, theta_jacobian, offset_jacobian;
  };

  const Jets* cached(const double* theta, const double* offset) const {
    const std::size_t nf = free_.size();
    for (const Jets& c : cache_)
      if (c.valid && std::equal(theta, theta + nf, c.at.begin()) &&
          std::equal(offset, offset + kOffsets, c.at.begin() + static_cast<std::ptrdiff_t>(nf)))
        return &c;
    return nullptr;
  }

  bool normal_sums(const double* theta, const double* offset, Eigen::MatrixXd& jtj, Eigen::VectorXd& jtr,
                   double& rss) const override {
    const auto mm = static_cast<Eigen::Index>(columns());
    Eigen::Matrix<double, N, N> jtj_n;
    Eigen::Matrix<double, N, 1> jtr_n;
    if (!accumulate(theta, offset, jtj_n, jtr_n, rss)) return false;
    jtj = jtj_n.topLeftCorner(mm, mm);
    jtr = jtr_n.head(mm);
    return true;
  }

 private:
  // The simulation with Jets: J^T J, J^T r (derivative slots beyond the columns zero) and r^T r.
  bool accumulate(const double* theta, const double* offset, Eigen::Matrix<double, N, N>& jtj_n,
                  Eigen::Matrix<double, N, 1>& jtr_n, double& rss) const {
    const std::size_t nf = free_.size();
    using Jet = ceres::Jet<double, N>;
    ParamVector<Jet> p;
    for (int i = 0; i < kNumParams; ++i) p[i] = Jet(fixed_[i]);
    for (std::size_t j = 0; j < nf; ++j) {
      const double value = free_.to_physical(j, theta[j]);
      p[free_.index[j]] = Jet(value, static_cast<int>(j));
      p[free_.index[j]].v[static_cast<int>(j)] = free_.slope(j, value);  // chain rule into internal coordinates
    }
    const model::InitialOffsets<Jet> start{Jet(offset[0], static_cast<int>(nf)), Jet(offset[1], static_cast<int>(nf) + 1)};
    // J^T J and J^T r summed a batch of residuals at a time: a product of a kBatch x N block with
    // itself (vectorized, cache-resident) instead of a rank-one update per residual, which took a
    // fifth of the fit. Derivative slots beyond the m columns are zero throughout.
    constexpr int kBatch = 64;
    using Rows = Eigen::Matrix<double, kBatch, N, Eigen::RowMajor>;
    Rows rows;
    Eigen::Matrix<double, kBatch, 1> values;
    jtj_n.setZero();
    jtr_n.setZero();
    int filled = 0;
    const auto flush = [&] {
      const auto block = rows.topRows(filled);
      jtj_n.noalias() += block.transpose() * block;
      jtr_n.noalias() += block.transpose() * values.head(filled);
      filled = 0;
    };
    rss = 0;
    const bool ok = fill(model::with_cooling_factor(p, cooling_), start, [&](const Jet& e) {
      rows.row(filled) = e.v.transpose();
      values(filled) = e.a;
      rss += e.a * e.a;
      if (++filled == kBatch) flush();
    });
    if (filled > 0) flush();
    return ok;
  }

  // The compressed residuals and both Jacobians, into the cache in place of the older point
  // (rows past the informative ones, and the last row, stay zero); null where not finite.
  const Jets* evaluate_jets(const double* theta, const double* offset) const {
    const std::size_t nf = free_.size(), m = columns();
    Jets& c = cache_[oldest_];
    oldest_ = 1 - oldest_;
    c.valid = false;
    std::fill(c.residuals.begin(), c.residuals.end(), 0.0);
    const auto mm = static_cast<Eigen::Index>(m);
    Eigen::Matrix<double, N, N> jtj_n;
    Eigen::Matrix<double, N, 1> jtr_n;
    double rss = 0;
    if (!accumulate(theta, offset, jtj_n, jtr_n, rss)) return nullptr;
    const Eigen::MatrixXd jtj = jtj_n.topLeftCorner(mm, mm);
    const Eigen::VectorXd jtr = jtr_n.head(mm);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(jtj);  // Lower: the default
    const Eigen::VectorXd& lambda = eig.eigenvalues();
    const double floor = 1e-14 * std::max(lambda.maxCoeff(), 0.0);
    double kept = 0;
    for (Eigen::Index k = 0; k < mm; ++k) {
      const auto row = static_cast<std::size_t>(k);
      const double l = lambda(k);
      const bool informative = l > floor && l > 0;
      const Eigen::VectorXd v = eig.eigenvectors().col(k);
      if (informative) {
        c.residuals[row] = v.dot(jtr) / std::sqrt(l);
        kept += c.residuals[row] * c.residuals[row];
      }
      const double scale = informative ? std::sqrt(l) : 0.0;
      for (std::size_t j = 0; j < nf; ++j) c.theta_jacobian[row * nf + j] = scale * v(static_cast<Eigen::Index>(j));
      for (int j = 0; j < kOffsets; ++j)
        c.offset_jacobian[row * kOffsets + static_cast<std::size_t>(j)] = scale * v(static_cast<Eigen::Index>(nf) + j);
    }
    c.residuals[m] = std::sqrt(std::max(0.0, rss - kept));
    std::copy(theta, theta + nf, c.at.begin());
    std::copy(offset, offset + kOffsets, c.at.begin() + static_cast<std::ptrdiff_t>(nf));
    c.valid = true;
    return &c;
  }

  std::size_t columns() const { return free_.size() + kOffsets; }

  template <class T, class Put>
  bool fill(const ParamVector<T>& p, const model::InitialOffsets<T>& start, Put&& put) const {
    return calibrate::for_each_grid_residual(model_, p, cycle_, start, put, max_steps_, prepared_);
  }

  const Model<double>& model_;
  const data::Cycle& cycle_;
  const calibrate::FreeParameters& free_;
  const ParamVector<double>& fixed_;
  std::size_t max_steps_;
  double cooling_;  // the cycle's motor's cooling factor (1 outside a fleet)
  const model::PreparedCycle* prepared_;  // the cycle's inputs prepared once (the dataset's), or null
  // The last two Jet evaluations (Ceres evaluates one block from one thread at a time); oldest_
  // the one the next evaluation replaces.
  mutable std::array<Jets, 2> cache_;
  mutable std::size_t oldest_ = 0;
  // The last cost evaluated without derivatives: where, its sum of squares, whether finite.
  struct Plain {
    bool valid = false, ok = false;
    double rss = 0;
    std::vector<double> at;
  };
  mutable Plain plain_;
};

// The smallest Jet that carries `n` derivatives.
CycleBlock* make_residuals(const Model<double>& model, const data::Cycle& cycle, const calibrate::FreeParameters& free,
                           const ParamVector<double>& fixed, std::size_t max_steps, double cooling = 1.0,
                           const model::PreparedCycle* prepared = nullptr) {
  const std::size_t n = free.size() + kOffsets;
  if (n <= 4) return new CycleResiduals<4>(model, cycle, free, fixed, max_steps, cooling, prepared);
  // The paper's six conductances and the two offsets: a width that vectorizes without a remainder.
  if (n <= 8) return new CycleResiduals<8>(model, cycle, free, fixed, max_steps, cooling, prepared);
  if (n <= 10) return new CycleResiduals<10>(model, cycle, free, fixed, max_steps, cooling, prepared);
  // The paper's parameters with an effect or a dictionary term or two (the usual calibration and
  // every refit of diagnose): a Jet sized by the whole library would carry mostly zeros.
  if (n <= 16) return new CycleResiduals<16>(model, cycle, free, fixed, max_steps, cooling, prepared);
  if (n <= 24) return new CycleResiduals<24>(model, cycle, free, fixed, max_steps, cooling, prepared);
  // Every parameter of the library free: sized by the library, so that registering an effect
  // (docs/effects.md) needs nothing here.
  return new CycleResiduals<std::max(18, kNumParams + kOffsets)>(model, cycle, free, fixed, max_steps, cooling, prepared);
}


// Every cycle's compressed block, evaluated by the process that holds the cycle and joined over
// the processes (a sum in which each element has one non-zero term, so exact): Ceres, on every
// rank, then sees the blocks of the whole dump and takes the steps a single process would, while
// each rank simulates only its own cycles. Alone, the same path evaluates every block here.
//
// Ceres calls PrepareForEvaluation at each new point (the parameters already in place), then asks
// each SharedBlock, which copies its slot. The blocks are simulated here, on `threads` threads.
class SharedEvaluation final : public ceres::EvaluationCallback {
 public:
  SharedEvaluation(const hostio::ProcessGroup& group, int threads, std::size_t free_parameters)
      : group_(group), threads_(threads), nf_(free_parameters) {}

  // Slot layout: [failed] [m + 1 residuals] [(m + 1) x nf Jacobian] [(m + 1) x 2 Jacobian].
  std::size_t rows() const { return nf_ + kOffsets + 1; }
  std::size_t slot_size() const { return 1 + rows() * (1 + nf_ + kOffsets); }

  // A cycle's block: `local` where this process holds the cycle (owned here), null where another
  // does; `theta` and `offset` its parameter blocks. Returns its slot.
  std::size_t add(std::unique_ptr<CycleBlock> local, const double* theta, const double* offset) {
    blocks_.push_back(std::move(local));
    parameters_.push_back({theta, offset});
    buffer_.resize(blocks_.size() * slot_size());
    return blocks_.size() - 1;
  }

  void PrepareForEvaluation(bool evaluate_jacobians, bool /*new_evaluation_point*/) override {
    ++evaluations_;
    std::fill(buffer_.begin(), buffer_.end(), 0.0);
    hostio::parallel_for(blocks_.size(), threads_, [&](std::size_t b) {
      if (!blocks_[b]) return;
      double* slot = buffer_.data() + b * slot_size();
      double* residuals = slot + 1;
      double* jacobians[2] = {residuals + rows(), residuals + rows() + rows() * nf_};
      const bool ok = blocks_[b]->Evaluate(parameters_[b].data(), residuals, evaluate_jacobians ? jacobians : nullptr);
      slot[0] = ok ? 0.0 : 1.0;
    });
    const auto t0 = std::chrono::steady_clock::now();
    group_.sum(buffer_);
    join_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  const double* slot(std::size_t b) const { return buffer_.data() + b * slot_size(); }
  int evaluations() const { return evaluations_; }
  // Time in the sums over the processes (waiting for the slowest rank included), and their size.
  double join_seconds() const { return join_seconds_; }
  std::size_t joined_doubles() const { return buffer_.size(); }

 private:
  const hostio::ProcessGroup& group_;
  int threads_;
  std::size_t nf_;
  std::vector<std::unique_ptr<CycleBlock>> blocks_;
  std::vector<std::array<const double*, 2>> parameters_;
  std::vector<double> buffer_;
  int evaluations_ = 0;
  double join_seconds_ = 0;
};

// What Ceres sees of one cycle: its slot of the shared evaluation.
class SharedBlock final : public ceres::CostFunction {
 public:
  SharedBlock(const SharedEvaluation& shared, std::size_t slot, std::size_t free_parameters)
      : shared_(shared), slot_(slot), nf_(free_parameters) {
    set_num_residuals(static_cast<int>(shared.rows()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(nf_));
    mutable_parameter_block_sizes()->push_back(kOffsets);
  }
  bool Evaluate(double const* const* /*parameters*/, double* residuals, double** jacobians) const override {
    const double* slot = shared_.slot(slot_);
    const std::size_t rows = shared_.rows();
    std::copy(slot + 1, slot + 1 + rows, residuals);
    if (jacobians != nullptr) {
      if (jacobians[0] != nullptr) std::copy(slot + 1 + rows, slot + 1 + rows + rows * nf_, jacobians[0]);
      if (jacobians[1] != nullptr)
        std::copy(slot + 1 + rows + rows * nf_, slot + 1 + rows + rows * (nf_ + kOffsets), jacobians[1]);
    }
    return slot[0] == 0.0;
  }

 private:
  const SharedEvaluation& shared_;
  std::size_t slot_, nf_;
};

// Residual series (model - measured, demeaned per cycle) over the fitted cycles, per sensor:
// [0] the stator winding, [1] the rotor. One simulation per cycle serves both.
std::array<std::vector<std::vector<double>>, 2> residual_series(const Model<double>& model, const ParamVector<double>& p,
                                                               calibrate::DatasetRef dataset,
                                                               const std::vector<std::size_t>& cycles,
                                                               const std::vector<model::InitialOffsets<double>>& offsets,
                                                               const std::vector<double>& cooling, int threads,
                                                               std::array<calibrate::NoiseSum, 2>* noise = nullptr) {
  // Per cycle and sensor, simulated in parallel; then in the cycles' order, skipping the empty.
  std::vector<std::array<std::vector<double>, 2>> per_cycle(cycles.size());
  std::vector<std::array<calibrate::NoiseSum, 2>> per_cycle_noise(cycles.size());
  hostio::parallel_for(cycles.size(), threads, [&](std::size_t i) {
    if (dataset.remote(cycles[i])) return;  // its process takes its series
    const data::Cycle& cycle = dataset.cycles[cycles[i]];
    const ParamVector<double> pc = cooling.empty() ? p : model::with_cooling_factor(p, cooling[i]);
    const model::CycleSimulation sim = model::simulate_cycle(model, pc, cycle, offsets[i]);
    const std::pair<data::Channel, const std::vector<float>*> sensors[2] = {
        {data::Channel::stator_winding_c, &sim.stator_sensor}, {data::Channel::rotor_c, &sim.rotor_sensor}};
    for (int s = 0; s < 2; ++s) {
      std::vector<double>& r = per_cycle[i][static_cast<std::size_t>(s)];
      std::vector<float> on_grid(cycle.steps, std::numeric_limits<float>::quiet_NaN());  // for the noise
      double mean = 0;
      for (std::size_t k = 0; k < cycle.steps; ++k) {
        const float y = cycle.at(sensors[s].first, k);
        if (std::isnan(y)) continue;
        r.push_back(static_cast<double>((*sensors[s].second)[k]) - y);
        on_grid[k] = static_cast<float>(r.back());
        mean += r.back();
      }
      if (r.empty()) continue;
      if (noise != nullptr) {
        // White noise read every p grid steps and interpolated between stays correlated over about
        // p steps: its sum of squares scaled by p is what the residual variance is compared with.
        const std::size_t every = calibrate::reading_period(dataset.data, cycle, sensors[s].first);
        calibrate::NoiseSum n = calibrate::sensor_noise(on_grid, every);
        n.sum2 *= static_cast<double>(every);
        per_cycle_noise[i][static_cast<std::size_t>(s)] = n;
      }
      mean /= static_cast<double>(r.size());
      for (double& e : r) e -= mean;
    }
  });
  if (noise != nullptr) {
    // Pooled over the cycles and the processes.
    std::vector<double> sums(4, 0.0);
    for (std::size_t i = 0; i < cycles.size(); ++i)
      for (std::size_t s = 0; s < 2; ++s) {
        sums[2 * s] += per_cycle_noise[i][s].sum2;
        sums[2 * s + 1] += static_cast<double>(per_cycle_noise[i][s].n);
      }
    dataset.group().sum(sums);
    for (std::size_t s = 0; s < 2; ++s) (*noise)[s] = calibrate::NoiseSum{sums[2 * s], static_cast<std::size_t>(sums[2 * s + 1])};
  }
  std::array<std::vector<std::vector<double>>, 2> out;
  for (auto& c : per_cycle)
    for (std::size_t s = 0; s < 2; ++s)
      if (!c[s].empty()) out[s].push_back(std::move(c[s]));
  return out;
}

// J^T J of a Jacobian evaluated by Ceres (CRS: each row's non-zeros).
Eigen::MatrixXd gram(const ceres::CRSMatrix& jacobian) {
  Eigen::MatrixXd jtj = Eigen::MatrixXd::Zero(jacobian.num_cols, jacobian.num_cols);
  for (int r = 0; r < jacobian.num_rows; ++r) {
    const int begin = jacobian.rows[static_cast<std::size_t>(r)], end = jacobian.rows[static_cast<std::size_t>(r) + 1];
    for (int a = begin; a < end; ++a)
      for (int b = begin; b < end; ++b)
        jtj(jacobian.cols[static_cast<std::size_t>(a)], jacobian.cols[static_cast<std::size_t>(b)]) +=
            jacobian.values[static_cast<std::size_t>(a)] * jacobian.values[static_cast<std::size_t>(b)];
  }
  return jtj;
}

class Progress final : public ceres::IterationCallback {
 public:
  Progress(const LmProgress& progress, const std::function<bool(int, double)>& stop, std::size_t residuals,
           std::chrono::steady_clock::time_point start)
      : progress_(progress), stop_(stop), residuals_(residuals), start_(start) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (progress_) {
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
      progress_(s.iteration, std::sqrt(2.0 * s.cost / static_cast<double>(residuals_)), seconds);
    }
    return stop_ && stop_(s.iteration, s.cost) ? ceres::SOLVER_TERMINATE_SUCCESSFULLY : ceres::SOLVER_CONTINUE;
  }

 private:
  const LmProgress& progress_;
  const std::function<bool(int, double)>& stop_;
  std::size_t residuals_;
  std::chrono::steady_clock::time_point start_;
};


// What one fit tells the identifiability judgement beyond its report.
struct FitExtras {
  bool judge = false;          // stop before solving where a free parameter moves nothing
  bool check_only = false;     // stop before solving in any case (the start's checks only)
  std::vector<int> blind;      // model indices of free parameters with no effect on the residuals at the start
  // per free parameter: its 1-sigma error in internal coordinates with the other parameters known,
  // at the sensors' noise (judge only; inf: the data does not move it)
  std::vector<double> conditional_log_std;
};

LmReport fit_once(const model::MotorFile& motor, const ParamVector<double>& start, calibrate::DatasetRef dataset,
                  const std::vector<std::size_t>& cycles, const LmSettings& settings, const LmProgress& progress,
                  const std::vector<double>& cooling, FitExtras& extras) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!cooling.empty() && cooling.size() != cycles.size())
    throw std::invalid_argument("fit_lm: one cooling factor per cycle, or none");
  const Model<double> model = motor.model();
  const calibrate::FreeParameters free = calibrate::FreeParameters::from_motor(motor);
  const std::size_t nf = free.size();
  LmReport report;
  report.values = start;
  report.std_error.fill(std::nan(""));
  if (nf == 0) throw std::runtime_error("no parameter is marked for calibration in " + motor.path.string());

  std::vector<double> theta(nf);
  for (std::size_t j = 0; j < nf; ++j) {
    const double v = std::clamp(start[free.index[j]], free.min[j], free.max[j]);
    theta[j] = free.to_internal(j, v);
  }

  const hostio::ProcessGroup& group = dataset.group();
  report.mpi_ranks = group.size();
  SharedEvaluation shared(group, settings.threads, nf);
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  problem_options.evaluation_callback = &shared;
  ceres::Problem problem(problem_options);
  report.offsets.assign(cycles.size(), model::InitialOffsets<double>{});
  std::vector<std::array<double, kOffsets>> offsets(cycles.size(), {0.0, 0.0});
  if (!settings.start_offsets.empty()) {
    if (settings.start_offsets.size() != cycles.size())
      throw std::invalid_argument("fit_lm: start_offsets: one per cycle, or none");
    for (std::size_t i = 0; i < cycles.size(); ++i) {
      offsets[i][0] = std::clamp(settings.start_offsets[i].stator_core, -model::kInitialOffsetBoundK, model::kInitialOffsetBoundK);
      offsets[i][1] = std::clamp(settings.start_offsets[i].rotor_core, -model::kInitialOffsetBoundK, model::kInitialOffsetBoundK);
    }
  }
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  std::size_t local_residuals = 0;  // of the cycles this process simulates
  for (std::size_t i = 0; i < cycles.size(); ++i) {
    const data::Cycle& cycle = dataset.cycles[cycles[i]];
    const std::size_t measured = dataset.residuals(cycles[i]);
    if (measured == 0) continue;
    report.residuals += measured;
    std::unique_ptr<CycleBlock> local;
    if (!dataset.remote(cycles[i])) {
      local_residuals += measured;
      local.reset(make_residuals(model, cycle, free, start, SIZE_MAX, cooling.empty() ? 1.0 : cooling[i],
                                 dataset.prepared(cycles[i])));
    }
    const std::size_t slot = shared.add(std::move(local), theta.data(), offsets[i].data());
    problem.AddResidualBlock(new SharedBlock(shared, slot, nf), nullptr, theta.data(), offsets[i].data());
    ordering->AddElementToGroup(offsets[i].data(), 0);  // eliminated first: the Schur complement
    for (int j = 0; j < kOffsets; ++j) {
      problem.SetParameterLowerBound(offsets[i].data(), j, -model::kInitialOffsetBoundK);
      problem.SetParameterUpperBound(offsets[i].data(), j, model::kInitialOffsetBoundK);
    }
  }
  if (report.residuals == 0) throw std::runtime_error("no training cycle has a stator or rotor measurement");
  {
    // Each process's share of the work (its cycles' residuals), for the balance it reports.
    std::vector<double> share(static_cast<std::size_t>(group.size()), 0.0);
    share[static_cast<std::size_t>(group.rank())] = static_cast<double>(local_residuals);
    group.sum(share);
    for (double n : share) report.rank_residuals.push_back(static_cast<std::size_t>(n));
  }
  for (std::size_t j = 0; j < nf; ++j) {
    problem.SetParameterLowerBound(theta.data(), static_cast<int>(j), free.to_internal(j, free.min[j]));
    problem.SetParameterUpperBound(theta.data(), static_cast<int>(j), free.to_internal(j, free.max[j]));
  }

  // Before any iteration: the model must simulate at the start (a motor file whose values run
  // away gives non-finite residuals, which Ceres' linear algebra must never see), and each free
  // parameter must move the residuals at all. The Jacobian found here is the one the first
  // iteration needs (CycleResiduals keeps it), so this costs no simulation.
  {
    ceres::CRSMatrix j0;
    double cost0 = 0;
    ceres::Problem::EvaluateOptions at_start;
    at_start.parameter_blocks = {theta.data()};
    at_start.num_threads = 1;
    const bool ok = problem.Evaluate(at_start, &cost0, nullptr, nullptr, &j0);
    Eigen::VectorXd information = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(nf));
    if (ok && std::isfinite(cost0)) {
      const Eigen::MatrixXd jtj0 = gram(j0);
      information = jtj0.diagonal();
    }
    if (!ok || !std::isfinite(cost0) || !information.allFinite())
      throw ModelNotSimulable("the model cannot be simulated on the training data with the motor file's values "
                              "(temperatures or losses not finite at the start)");
    const double most = information.maxCoeff();
    for (std::size_t j = 0; j < nf; ++j)
      if (!(information(static_cast<Eigen::Index>(j)) > 1e-12 * most)) extras.blind.push_back(free.index[j]);
    if (extras.check_only || (extras.judge && !extras.blind.empty())) return report;
  }

  ceres::Solver::Options options;
  options.minimizer_type = ceres::TRUST_REGION;
  options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  // Each cycle's two offsets touch only its own block: eliminated cycle by cycle (Schur), the
  // linear algebra grows linearly with the cycles (a dense QR over every offset grows with their cube).
  options.linear_solver_type = ceres::DENSE_SCHUR;
  ordering->AddElementToGroup(theta.data(), 1);
  options.linear_solver_ordering = ordering;
  options.max_num_iterations = settings.max_iterations;
  // The projected line search Ceres takes for the bounds (each step) fits a quadratic through the
  // start's cost and slope and its trials' costs: no trial is differentiated. With the cubic (the
  // default) each trial was a simulation with every derivative, and where the step is cut back (a
  // refit crawling along a direction the data barely support) one LM iteration on the 200 h dump's
  // 0.1 s grid took 19 s instead of 2.3. An accepted trial is the step's candidate point, whose
  // cost CycleResiduals keeps.
  options.line_search_interpolation_type = ceres::QUADRATIC;
  // That line search shortens a step whose cost does not fall enough, up to 20 times by default
  // (each a simulation of the data). Where a step is still not good after three (a fit at its
  // optimum, where cost changes are rounding; a refit crawling along a flat direction) the search
  // gives up, the full step is tried and rejected, and the trust region shrinks, as it would have
  // after twenty: on the 200 h dump's diagnosis one polish spent 19 simulations (10 s) to find a
  // step of 1e-12 that ended it, and the crawling refits 20 at each rejected step. The 48 h and
  // 200 h calibrations and both diagnoses are unchanged to the last printed digit.
  options.max_num_line_search_step_size_iterations = 4;
  options.function_tolerance = settings.function_tolerance;
  options.parameter_tolerance = settings.parameter_tolerance;
  // The simulations run in SharedEvaluation on settings.threads; what Ceres does with the blocks
  // is copying and small sums, kept in one thread so that every rank adds in the same order.
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  Progress callback(progress, settings.stop, report.residuals, t0);
  options.callbacks.push_back(&callback);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);

  report.iterations = static_cast<int>(summary.iterations.size()) - 1;
  report.initial_cost = summary.initial_cost;
  report.final_cost = summary.final_cost;
  report.converged = summary.termination_type == ceres::CONVERGENCE;
  report.termination = summary.message;
  report.rmse_k = std::sqrt(2.0 * summary.final_cost / static_cast<double>(report.residuals));
  report.evaluations = shared.evaluations();
  report.joined_doubles = shared.joined_doubles();
  report.join_seconds = shared.join_seconds();
  report.linear_solver_seconds = summary.linear_solver_time_in_seconds;
  for (std::size_t j = 0; j < nf; ++j) report.values[free.index[j]] = free.to_physical(j, theta[j]);
  for (std::size_t i = 0; i < cycles.size(); ++i) report.offsets[i] = {offsets[i][0], offsets[i][1]};

  // Uncertainty from the Gauss-Newton approximation at the optimum: cov = s^2 (J^T J)^-1 with
  // s^2 the residual variance, inflated by the residuals' correlation time (correlation_time):
  // consecutive grid residuals are not independent, and treating them so would claim far too
  // small errors.
  ceres::CRSMatrix jacobian;
  double cost = 0;
  // The per-cycle offsets are nuisance parameters here: the Jacobian is taken for the model's
  // parameters with the offsets held at their estimates.
  // (A listed cycle without a measurement has no block, and its offsets are not in the problem.)
  for (auto& o : offsets)
    if (problem.HasParameterBlock(o.data())) problem.SetParameterBlockConstant(o.data());
  ceres::Problem::EvaluateOptions evaluate;
  evaluate.parameter_blocks = {theta.data()};
  evaluate.num_threads = 1;
  problem.Evaluate(evaluate, &cost, nullptr, nullptr, &jacobian);
  const Eigen::MatrixXd jtj = gram(jacobian);
  const double dof = std::max(1.0, static_cast<double>(report.residuals) - static_cast<double>(nf));
  std::array<calibrate::NoiseSum, 2> noise{};  // scaled by each sensor's reading period (residual_series)
  const auto series = residual_series(model, report.values, dataset, cycles, report.offsets, cooling, settings.threads,
                                      extras.judge ? &noise : nullptr);
  std::array<double, 2> tau{};
  for (std::size_t s = 0; s < 2; ++s) {
    std::vector<double> sums = correlation_sums(series[s], settings.threads);
    group.sum(sums);
    tau[s] = correlation_time_of_sums(sums);
  }
  report.correlation_time = std::max(tau[0], tau[1]);
  const double s2 = 2.0 * cost / dof * report.correlation_time;
  if (!jtj.allFinite() || !std::isfinite(s2)) {
    report.converged = false;
    report.termination = "the fit ended where the model's residuals are not finite";
    report.at_bound.assign(nf, false);
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return report;
  }
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(jtj);
  const Eigen::MatrixXd cov = s2 * cod.pseudoInverse();
  const bool full_rank = cod.rank() == static_cast<Eigen::Index>(nf);
  if (extras.judge) {
    // Identifiability asks what the data could pin were the model right: the errors scaled from
    // the residual's variance (a model that lacks physics has a large, slow misfit, which inflates
    // them) to the sensors' own noise, white at their reading period (sensor_noise.hpp). Never
    // above the fit's own errors.
    double noise_var = 0, weight = 0;
    for (std::size_t k = 0; k < 2; ++k) {
      const double sigma = noise[k].sigma();
      if (!std::isfinite(sigma) || noise[k].n == 0) continue;
      noise_var += static_cast<double>(noise[k].n) * sigma * sigma;
      weight += static_cast<double>(noise[k].n);
    }
    const double ratio = weight > 0 && s2 > 0 ? std::min(1.0, noise_var / weight / s2) : 1.0;
    // A parameter is judged by what the data tells of it with the others known (its own
    // information, J^T J's diagonal): one that is pinned only together with a partner (a
    // combination the data pins better than its parts) stays free, a correlation note.
    extras.conditional_log_std.assign(nf, 0.0);
    for (std::size_t j = 0; j < nf; ++j) {
      const double info = jtj(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(j));
      extras.conditional_log_std[j] = info > 0 ? std::sqrt(s2 * ratio / info) : std::numeric_limits<double>::infinity();
    }
  }
  report.correlation.assign(nf, std::vector<double>(nf, 0.0));
  report.at_bound.assign(nf, false);
  for (std::size_t a = 0; a < nf; ++a) {
    const auto ia = static_cast<Eigen::Index>(a);
    const double value = report.values[free.index[a]];
    report.at_bound[a] = std::abs(theta[a] - free.to_internal(a, free.min[a])) < 1e-6 ||
                         std::abs(theta[a] - free.to_internal(a, free.max[a])) < 1e-6;
    if (full_rank && cov(ia, ia) > 0) report.std_error[free.index[a]] = free.slope(a, value) * std::sqrt(cov(ia, ia));
    for (std::size_t b = 0; b < nf; ++b) {
      const auto ib = static_cast<Eigen::Index>(b);
      const double d = std::sqrt(cov(ia, ia) * cov(ib, ib));
      report.correlation[a][b] = d > 0 ? cov(ia, ib) / d : (a == b ? 1.0 : 0.0);
    }
  }
  for (std::size_t a = 0; a < nf; ++a)
    for (std::size_t b = a + 1; b < nf; ++b)
      if (std::abs(report.correlation[a][b]) >= settings.correlation_flag)
        report.correlated.push_back({std::string(param_spec(free.index[a]).name),
                                     std::string(param_spec(free.index[b]).name), report.correlation[a][b]});
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}


// Whether any of the listed cycles has a rotor reading (over every process of a shared dataset).
bool any_rotor_reading(calibrate::DatasetRef dataset, const std::vector<std::size_t>& cycles) {
  std::vector<double> found{0.0};
  for (std::size_t c : cycles)
    if (!dataset.remote(c) && dataset.cycles[c].has(data::Channel::rotor_c)) found[0] = 1.0;
  dataset.group().sum(found);
  return found[0] > 0;
}

std::string blind_reason(bool rotor_readings) {
  return rotor_readings ? "it does not change what the sensors read on the training data (an input it acts through may "
                          "be absent or constant): fixed at the motor file's value"
                        : "no rotor readings in the training data, and it does not reach the stator winding sensor: it "
                          "moves only nodes no sensor sees; fixed at the motor file's value";
}

std::string weak_reason(const calibrate::FreeParameters& free, std::size_t j, double log_std, const LmReport& fit) {
  char buf[240];
  if (!std::isfinite(log_std) || (free.log_scale[j] && log_std > std::log(1000.0)))
    std::snprintf(buf, sizeof buf, "the training data hardly moves it (known only within a factor over 1000 at 1 sigma)");
  else if (free.log_scale[j])
    std::snprintf(buf, sizeof buf, "even with the other parameters known, the training data pins it only within a factor of %.3g at 1 sigma", std::exp(log_std));
  else
    std::snprintf(buf, sizeof buf, "even with the other parameters known, the training data pins it only to +-%.3g at 1 sigma (its range is %g..%g)", log_std,
                  free.min[j], free.max[j]);
  std::string out = buf;
  // The partner it is confounded with, where one stands out.
  std::size_t partner = j;
  double strongest = 0;
  for (std::size_t b = 0; b < free.size() && j < fit.correlation.size(); ++b)
    if (b != j && std::abs(fit.correlation[j][b]) > strongest) {
      strongest = std::abs(fit.correlation[j][b]);
      partner = b;
    }
  if (partner != j && strongest >= 0.9) {
    std::snprintf(buf, sizeof buf, " (%+.2f correlated with %s)", fit.correlation[j][partner],
                  std::string(param_spec(free.index[partner]).name).c_str());
    out += buf;
  }
  return out + "; fixed at the motor file's value";
}

}  // namespace

std::vector<NotIdentifiable> unseen_parameters(const model::MotorFile& motor, const ParamVector<double>& start,
                                               calibrate::DatasetRef dataset, const std::vector<std::size_t>& cycles) {
  FitExtras extras;
  extras.judge = true;
  extras.check_only = true;
  LmSettings settings;
  fit_once(motor, start, dataset, cycles, settings, {}, {}, extras);
  const bool rotor_readings = any_rotor_reading(dataset, cycles);
  std::vector<NotIdentifiable> out;
  for (int i : extras.blind) out.push_back({i, blind_reason(rotor_readings)});
  return out;
}

LmReport fit_lm(const model::MotorFile& motor, const ParamVector<double>& start, calibrate::DatasetRef dataset,
                const std::vector<std::size_t>& cycles, const LmSettings& settings, const LmProgress& progress,
                const std::vector<double>& cooling) {
  if (!settings.judge_identifiability) {
    FitExtras extras;
    return fit_once(motor, start, dataset, cycles, settings, progress, cooling, extras);
  }
  // Fix what the data cannot pin, one parameter at a time (the least pinned first: fixing it
  // may pin its partner), and refit the rest from where the last fit ended.
  const auto t0 = std::chrono::steady_clock::now();
  const bool rotor_readings = any_rotor_reading(dataset, cycles);
  model::MotorFile m = motor;
  ParamVector<double> from = start;
  std::vector<NotIdentifiable> fixed;
  for (;;) {
    FitExtras extras;
    extras.judge = true;
    const calibrate::FreeParameters free = calibrate::FreeParameters::from_motor(m);
    if (free.size() == 0 && !fixed.empty())
      throw std::runtime_error("no parameter this data can pin: " + fixed.front().reason);
    LmReport fit = fit_once(m, from, dataset, cycles, settings, progress, cooling, extras);
    if (!extras.blind.empty()) {
      for (int i : extras.blind) {
        fixed.push_back({i, blind_reason(rotor_readings)});
        m.parameters[static_cast<std::size_t>(i)].calibrate = false;
      }
      continue;
    }
    std::size_t worst = free.size();
    double worst_excess = 1.0;
    for (std::size_t j = 0; j < free.size() && j < extras.conditional_log_std.size(); ++j) {
      const double bound = free.log_scale[j] ? settings.max_log_std : 0.25 * (free.max[j] - free.min[j]);
      const double excess = extras.conditional_log_std[j] / bound;
      if (excess > worst_excess) {
        worst_excess = excess;
        worst = j;
      }
    }
    if (worst < free.size() && free.size() > 1) {
      const int i = free.index[worst];
      fixed.push_back({i, weak_reason(free, worst, extras.conditional_log_std[worst], fit)});
      m.parameters[static_cast<std::size_t>(i)].calibrate = false;
      from = fit.values;
      from[i] = start[i];
      continue;
    }
    fit.not_identifiable = fixed;
    for (const NotIdentifiable& n : fixed) {
      fit.values[n.index] = start[n.index];
      fit.std_error[n.index] = std::nan("");
    }
    fit.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return fit;
  }
}

NormalEquations normal_equations(const Model<double>& model, const calibrate::FreeParameters& free, const ParamVector<double>& at,
                                 calibrate::DatasetRef dataset, const std::vector<std::size_t>& cycles,
                                 const std::vector<model::InitialOffsets<double>>& offsets, int threads) {
  // Computed whole on every process: the cycles' samples must be here (share_work's, not load_shared_dump's).
  for (std::size_t c : cycles) {
    const data::Cycle& cycle = dataset.cycles[c];
    if (dataset.remote(c) && std::all_of(cycle.samples.begin(), cycle.samples.end(), [](const auto& v) { return v.empty(); }))
      throw std::logic_error("normal_equations: cycle " + cycle.name + " is held by another process");
  }
  const std::size_t nf = free.size();
  std::vector<double> theta(nf);
  for (std::size_t j = 0; j < nf; ++j) theta[j] = free.to_internal(j, at[free.index[j]]);
  NormalEquations out;
  // Each cycle's sums as they are (not the compressed blocks LM sees: a direction the compression
  // drops, nearly null in J^T J, still carries a share of J^T r, and a score test restricted to
  // some of the columns would miss it). A cycle without measurements has no offsets' columns.
  struct CycleSums {
    std::unique_ptr<CycleBlock> block;
    std::array<double, kOffsets> offset{};
    Eigen::MatrixXd jtj;
    Eigen::VectorXd jtr;
    double rss = 0;
    bool ok = true;
  };
  std::vector<CycleSums> sums;
  for (std::size_t i = 0; i < cycles.size(); ++i) {
    std::unique_ptr<CycleBlock> block(
        make_residuals(model, dataset.cycles[cycles[i]], free, at, SIZE_MAX, 1.0, dataset.prepared(cycles[i])));
    out.residuals += block->measured();
    if (block->measured() == 0) continue;
    sums.push_back({std::move(block), {offsets[i].stator_core, offsets[i].rotor_core}, {}, {}, 0, true});
  }
  hostio::parallel_for(sums.size(), threads, [&](std::size_t i) {
    CycleSums& c = sums[i];
    c.ok = c.block->normal_sums(theta.data(), c.offset.data(), c.jtj, c.jtr, c.rss);
  });
  const auto p = static_cast<Eigen::Index>(nf);
  const Eigen::Index m = p + static_cast<Eigen::Index>(kOffsets * sums.size());
  Eigen::MatrixXd jtj = Eigen::MatrixXd::Zero(m, m);
  Eigen::VectorXd jtr = Eigen::VectorXd::Zero(m);
  for (std::size_t i = 0; i < sums.size(); ++i) {
    const CycleSums& c = sums[i];
    if (!c.ok) {
      out.rss = std::numeric_limits<double>::quiet_NaN();
      jtr.setConstant(out.rss);
      continue;
    }
    const Eigen::Index o = p + static_cast<Eigen::Index>(kOffsets * i);
    jtj.topLeftCorner(p, p) += c.jtj.topLeftCorner(p, p);
    jtj.block(0, o, p, kOffsets) = c.jtj.topRightCorner(p, kOffsets);
    jtj.block(o, 0, kOffsets, p) = c.jtj.bottomLeftCorner(kOffsets, p);
    jtj.block(o, o, kOffsets, kOffsets) = c.jtj.bottomRightCorner(kOffsets, kOffsets);
    jtr.head(p) += c.jtr.head(p);
    jtr.segment(o, kOffsets) = c.jtr.tail(kOffsets);
    out.rss += c.rss;
  }
  out.columns = static_cast<std::size_t>(m);
  out.jtj.assign(jtj.data(), jtj.data() + jtj.size());  // symmetric: column-major equals row-major
  out.jtr.assign(jtr.data(), jtr.data() + jtr.size());
  return out;
}

}  // namespace lptn::lm
