// A fleet dump shared over the processes of an MPI job (hostio/process_group.hpp), so that no
// process holds the whole dump: each loads only its own units (files, or a fleet's motors: unit u
// belongs to rank u mod ranks) and learns of every other cycle its name, file, grid, residual
// count and file hash (a remote cycle, CycleShare::remote). Every rank then holds the same list of
// cycles in the same order as a single process's load, so that splits, indices and results agree.
// The data layer knows nothing of this: which process holds a cycle is the calibrate layer's
// (SharedDataset), and the computations that share their work read a dataset through DatasetRef.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "hostio/process_group.hpp"
#include "trainer/calibrate/grid_residuals.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn::calibrate {

// Where a cycle of a shared dataset is held.
struct CycleShare {
  // Held by another process: its name, file and grid are known here, its samples maybe not
  // (load_shared_dump's are not; share_work's stay, only the shared computations leave it).
  bool remote = false;
  std::size_t residuals = 0;  // remote: its count_grid_residuals, from the process that holds it
  std::string file_sha256;    // the file's hash where the loading process took it already, else empty
};

// A dataset and, where it is shared over the processes of an MPI job, where each cycle is held.
struct SharedDataset {
  data::Dataset data;
  std::vector<CycleShare> shares;  // one per cycle where shared; empty where this process holds them all
  bool shared() const { return !shares.empty(); }
  // Each cycle's inputs as the model prepares them (model::prepare_cycle), for a caller that fits
  // many models of one motor on it (diagnose's refits on the 1 s grid): prepared with the motor
  // constants of every model fitted on it (effects and parameters do not enter). Empty, or one per
  // cycle, empty for a cycle not prepared: the fits then prepare each step as they go.
  std::vector<model::PreparedCycle> prepared;
};

// A dataset as the computations that share their work read it (fit_lm, evaluate_split, the fleet's
// fit): every cycle, and, where it is shared, which are another process's. Made implicitly from a
// plain dataset (this process holds every cycle) or a shared one; it refers to it, so it lives in
// a call's arguments, not beyond.
class DatasetRef {
 public:
  DatasetRef(const data::Dataset& dataset) : cycles(dataset.cycles), data(dataset) {}  // NOLINT: implicit on purpose
  DatasetRef(const SharedDataset& dataset)  // NOLINT: implicit on purpose
      : cycles(dataset.data.cycles),
        data(dataset.data),
        shares_(dataset.shared() ? &dataset.shares : nullptr),
        prepared_(dataset.prepared.empty() ? nullptr : &dataset.prepared) {}
  DatasetRef(data::Dataset&&) = delete;  // a reference to a temporary would dangle
  DatasetRef(SharedDataset&&) = delete;

  const std::vector<data::Cycle>& cycles;
  const data::Dataset& data;

  bool shared() const { return shares_ != nullptr; }
  // Held by another process (its samples may be absent; its results come from that process).
  bool remote(std::size_t cycle) const { return shares_ != nullptr && (*shares_)[cycle].remote; }
  // count_grid_residuals of the cycle, wherever it is held.
  std::size_t residuals(std::size_t cycle) const {
    return remote(cycle) ? (*shares_)[cycle].residuals : count_grid_residuals(cycles[cycle]);
  }
  // The hash of the cycle's file where the loading process took it already, else empty.
  std::string file_sha256(std::size_t cycle) const { return shares_ != nullptr ? (*shares_)[cycle].file_sha256 : std::string(); }
  // The processes the dataset is shared over: the MPI job's where it is shared, else this one alone.
  const hostio::ProcessGroup& group() const { return shared() ? hostio::ProcessGroup::world() : hostio::ProcessGroup::alone(); }
  // The cycle's prepared inputs (SharedDataset::prepared), or null where there are none.
  const model::PreparedCycle* prepared(std::size_t cycle) const {
    if (prepared_ == nullptr || cycle >= prepared_->size() || (*prepared_)[cycle].empty()) return nullptr;
    return &(*prepared_)[cycle];
  }

 private:
  const std::vector<CycleShare>* shares_ = nullptr;
  const std::vector<model::PreparedCycle>* prepared_ = nullptr;
};

// Which rank loads unit `unit`.
inline int owner_of_unit(std::size_t unit, const hostio::ProcessGroup& group) {
  return static_cast<int>(unit % static_cast<std::size_t>(group.size()));
}

// One unit this rank loaded.
struct LoadedUnit {
  std::size_t unit = 0;
  data::Dataset data;
};

// Every unit's cycles on every rank, in unit order: this rank's `mine` whole (their file hashes
// taken), the others' remote. `units` is the number of units over all ranks; `unit_of_cycle`, if
// given, receives each cycle's unit. A collective call: every rank calls it, with its own units.
SharedDataset join_units(std::size_t units, std::vector<LoadedUnit> mine, const hostio::ProcessGroup& group,
                         std::vector<std::size_t>* unit_of_cycle = nullptr);

// data::load_fleet_dump with the files as units: the same cycles in the same order.
SharedDataset load_shared_dump(const std::vector<std::filesystem::path>& paths, const hostio::ProcessGroup& group,
                               const data::LoadOptions& options = {});

// Moves whole training cycles between the processes of a shared dataset so that each holds about
// the same share of the training residuals, the fit's work (a random split can leave one rank
// with 55 % of them on two). Deterministic: every rank plans the same moves from the same counts
// (from the most loaded rank to the least, the cycle that best halves their gap, while one does), and
// sends or receives its own. A collective call; alone, nothing happens.
void balance_training(SharedDataset& dataset, const std::vector<std::size_t>& train, const hostio::ProcessGroup& group);

// Shares the work on a dataset every process holds whole (loaded by each): the shared computations
// (fit_lm, evaluate_split, the correlation time) then simulate cycle i on rank i mod ranks only
// and join the results, while everything else still sees every cycle. For commands whose other
// work needs every cycle on every rank (lptn diagnose, whose LM refits are what takes long).
SharedDataset share_work(data::Dataset dataset, const hostio::ProcessGroup& group);

}  // namespace lptn::calibrate
