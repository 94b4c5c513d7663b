// The deterministic baseline: a Levenberg-Marquardt fit of the model to several cycles at once
// (Ceres), with exact derivatives through the whole simulation (Jets carried through every step
// of the integrator), bounds on every parameter, and the uncertainty the data leaves. On a dataset
// shared over the processes of an MPI job each process simulates its own cycles, and every
// process takes the steps a single one would (shared_dataset.hpp).
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "hostio/worker_threads.hpp"
#include "trainer/calibrate/calibration_file.hpp"  // CorrelatedPair
#include "trainer/calibrate/problem.hpp"

namespace lptn::lm {

struct LmSettings {
  int max_iterations = 60;
  double function_tolerance = 1e-9;   // relative change of the cost that ends the fit
  double parameter_tolerance = 1e-9;  // relative step that ends the fit
  int threads = hostio::worker_threads();     // residual blocks (cycles) evaluated in parallel
  double correlation_flag = 0.95;     // |correlation| from which a parameter pair is flagged
  // Judge which free parameters the data pins (docs/calibration.md, "Identifiability"): one
  // the data cannot move, or pins only within a factor of exp(max_log_std) at 1 sigma, is fixed
  // at its start and the rest refit. Off for diagnose's refits, which judge their terms otherwise.
  bool judge_identifiability = false;
  double max_log_std = 0.69314718055994531;  // ln 2: known within a factor of two at 1 sigma
  // Each listed cycle's initial offsets to start from (empty: zero), as a fit of the same cycles
  // ended them (diagnose's refit, polished on the fine grid after its steps on a coarse one).
  std::vector<InitialOffsets<double>> start_offsets;
  // Asked after every iteration with its number and the cost where the fit stands (half the sum of
  // squared residuals): true ends the fit there, not converged (diagnose's refits that cannot reach
  // their threshold at the pace they gain).
  std::function<bool(int iteration, double cost)> stop;
};

// A free parameter the data could not pin, left at its start (LmReport::not_identifiable).
struct NotIdentifiable {
  int index = -1;      // model parameter index
  std::string reason;  // in words, for calibration.json and the console
};

// The motor file's values give a model that cannot be simulated on the training data (losses or
// temperatures not finite at the start): nothing to fit. The message says so; the caller names
// the implausible values.
class ModelNotSimulable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct LmReport {
  ParamVector<double> values{};  // the fitted set (fixed parameters as given)
  ParamVector<double> std_error{};  // NaN where not calibrated or not identifiable
  std::vector<calibrate::CorrelatedPair> correlated;
  std::vector<std::vector<double>> correlation;  // free x free, order of FreeParameters::index
  std::vector<InitialOffsets<double>> offsets;  // per fitted cycle, in the order given
  std::vector<bool> at_bound;    // per free parameter: ended on its bound (its std error is then local only)
  // With judge_identifiability: the parameters fixed because the data could not pin them (then
  // not among the free ones above, std_error NaN, value the start's).
  std::vector<NotIdentifiable> not_identifiable;
  int iterations = 0;
  double initial_cost = 0, final_cost = 0;  // 1/2 sum of squared residuals, K^2
  std::size_t residuals = 0;
  double rmse_k = 0;  // over all residuals at the end (stator and rotor pooled)
  double correlation_time = 1;  // grid residuals per independent one (the std errors account for it)
  bool converged = false;
  std::string termination;
  double seconds = 0;
  int mpi_ranks = 1;  // the processes that shared the fit (the dataset's, trainer/calibrate/shared_dataset.hpp)
  std::vector<std::size_t> rank_residuals;  // per process: the residuals of the cycles it simulated
  // Where the time went, for the cost of sharing: the evaluations of every cycle (each one
  // simulation of the cycle, with or without Jets), the doubles each sums over the processes, the
  // seconds in those sums (waiting for the slowest rank included), and Ceres' linear algebra.
  int evaluations = 0;
  std::size_t joined_doubles = 0;
  double join_seconds = 0;
  double linear_solver_seconds = 0;
};

// Called after every iteration: (iteration, RMSE over all residuals in K, seconds so far).
using LmProgress = std::function<void(int, double, double)>;

// Fits the free parameters of `motor` starting from `start`, on the listed cycles, together with
// each cycle's initial offsets. Throws ModelNotSimulable if the model cannot be simulated at
// `start` (before any iteration). Residuals are
// model minus measurement of the stator winding sensor and, where measured, the rotor, at every
// grid step where the measurement exists. Throws std::runtime_error if no cycle has a measurement.
//
// `cooling` (empty, or one per listed cycle) is each cycle's known cooling factor
// (cooling_factor.hpp): a fleet's motors share the fitted parameters, each cycle simulated with
// its motor's conductances to air scaled (fleet_calibration.hpp).
LmReport fit_lm(const MotorFile& motor, const ParamVector<double>& start, calibrate::DatasetRef dataset,
                const std::vector<std::size_t>& cycles, const LmSettings& settings, const LmProgress& progress = {},
                const std::vector<double>& cooling = {});

// The free parameters of `motor` that move no residual of the listed cycles at `start` (for a
// calibrator that does not judge identifiability itself, TD3 and the search baselines: it then
// leaves them at the motor file's values). Throws ModelNotSimulable as fit_lm does.
std::vector<NotIdentifiable> unseen_parameters(const MotorFile& motor, const ParamVector<double>& start,
                                               calibrate::DatasetRef dataset, const std::vector<std::size_t>& cycles);

// The Gauss-Newton normal equations of fit_lm's problem at a given point, for tests of directions
// fit_lm did not search (lptn diagnose's score test). Columns: `free`'s parameters in its internal
// coordinates, then the two initial offsets (stator core, rotor core) of each cycle that has a
// measurement, in the order given.
struct NormalEquations {
  std::size_t columns = 0;
  std::vector<double> jtj;  // columns x columns, row-major
  std::vector<double> jtr;  // J^T r, r = model - measured
  double rss = 0;           // sum of squared residuals, K^2
  std::size_t residuals = 0;
};
NormalEquations normal_equations(const Model<double>& model, const calibrate::FreeParameters& free, const ParamVector<double>& at,
                                 calibrate::DatasetRef dataset, const std::vector<std::size_t>& cycles,
                                 const std::vector<InitialOffsets<double>>& offsets, int threads = hostio::worker_threads());

}  // namespace lptn::lm
