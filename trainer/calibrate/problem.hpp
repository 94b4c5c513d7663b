// What both calibrators share, so that their results compare: which parameters move and in which
// coordinates, the train/test split by cycle, and the metrics a parameter set earns on a split.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hostio/worker_threads.hpp"
#include "lptn/model.hpp"
#include "trainer/calibrate/metrics.hpp"
#include "trainer/calibrate/shared_dataset.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::calibrate {

// The parameters a calibration moves (those marked `calibrate` in the motor file) and their
// bounds. Calibrators work in internal coordinates: log(value) for a parameter searched on a log
// scale (uses_log_scale), the value itself otherwise, so that a step means the same relative
// change for a conductance of 5 W/K and one of 500 W/K.
struct FreeParameters {
  std::vector<int> index;  // model parameter indices
  std::vector<double> min, max;
  std::vector<bool> log_scale;

  static FreeParameters from_motor(const MotorFile& motor);
  std::size_t size() const { return index.size(); }
  double to_internal(std::size_t j, double value) const;
  double to_physical(std::size_t j, double internal) const;
  // d value / d internal at `value` (value for log scale, 1 for linear).
  double slope(std::size_t j, double value) const;
};

// Which cycles train and which test. Cycles are never cut: a test cycle is wholly unseen.
struct Split {
  std::vector<std::size_t> train, test;  // indices into Dataset::cycles
  std::string rule;                      // how it was chosen, for calibration.json
};

// `test_names` (exact cycle names) if given; otherwise a seeded random `test_fraction` of the
// cycles (at least one test and one train cycle when there are two or more). Throws
// BadInput naming an unknown cycle, or when no cycle is left to train on.
Split split_cycles(const data::Dataset& dataset, const std::vector<std::string>& test_names, double test_fraction,
                   std::uint64_t seed);

// One cycle as the metrics see it, whether it trained or not, so that train and test compare alike:
// the unmeasured nodes' initial offsets estimated from the cycle's first ten minutes
// (estimate_initial_offsets), the whole cycle simulated, and the model-minus-measurement metrics
// of the stator winding sensor and, where measured, the rotor.
struct CycleEvaluation {
  CycleSimulation simulation;
  CycleMetrics metrics;
};
// `prepared`, where given, is prepare_cycle()'s for this model and cycle: for a caller that
// evaluates one cycle at many parameter sets (diagnose's drift factors).
CycleEvaluation simulate_and_evaluate(const Model<double>& model, const ParamVector<double>& params,
                                      const data::Cycle& cycle, const PreparedCycle* prepared = nullptr);
// The model steps simulate_and_evaluate takes on a cycle (the offsets' three short runs and the
// cycle), for calibrators that report their simulation budget.
std::size_t evaluation_steps(const data::Cycle& cycle);
// The metrics alone.
CycleMetrics evaluate_cycle(const Model<double>& model, const ParamVector<double>& params, const data::Cycle& cycle,
                            const PreparedCycle* prepared = nullptr);
// Sets m.stator and m.rotor from m.cycles (the rotor over the cycles that measure it).
void pool_cycles(SplitMetrics& m);
// Every listed cycle and the pooled figures (cycles simulated in parallel on `threads`). Of a shared
// dataset, each process simulates the cycles it holds and every process gets every cycle's
// figures (a collective call).
SplitMetrics evaluate_split(const Model<double>& model, const ParamVector<double>& params, DatasetRef dataset,
                            const std::vector<std::size_t>& cycles, int threads = hostio::worker_threads());

}  // namespace lptn::calibrate
