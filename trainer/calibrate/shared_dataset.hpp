// A fleet dump shared over the processes of an MPI job (hostio/process_group.hpp), so that no
// process holds the whole dump: each loads only its own units (files, or a fleet's motors: unit u
// belongs to rank u mod ranks) and learns of every other cycle its name, file, grid, residual
// count and file hash (a remote cycle, data::Cycle::remote). Every rank then holds the same list of
// cycles in the same order as a single process's load, so that splits, indices and results agree.
#pragma once

#include <cstddef>
#include <filesystem>
#include <vector>

#include "hostio/process_group.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn {

// Which rank loads unit `unit`.
inline int owner_of_unit(std::size_t unit, const ProcessGroup& group) {
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
data::Dataset join_units(std::size_t units, std::vector<LoadedUnit> mine, const ProcessGroup& group,
                         std::vector<std::size_t>* unit_of_cycle = nullptr);

// data::load_fleet_dump with the files as units: the same cycles in the same order.
data::Dataset load_shared_dump(const std::vector<std::filesystem::path>& paths, const ProcessGroup& group,
                               const data::LoadOptions& options = {});

// Moves whole training cycles between the processes of a shared dataset so that each holds about
// the same share of the training residuals, the fit's work (a random split can leave one rank
// with 55 % of them on two). Deterministic: every rank plans the same moves from the same counts
// (from the most loaded rank to the least, the cycle that best halves their gap, while one does), and
// sends or receives its own. A collective call; alone, nothing happens.
void balance_training(data::Dataset& dataset, const std::vector<std::size_t>& train, const ProcessGroup& group);

// Shares the work on a dataset every process holds whole (loaded by each): the shared computations
// (fit_lm, evaluate_split, the correlation time) then simulate cycle i on rank i mod ranks only
// and join the results, while everything else still sees every cycle. For commands whose other
// work needs every cycle on every rank (lptn diagnose, whose LM refits are what takes long).
void share_work(data::Dataset& dataset, const ProcessGroup& group);

// The processes `dataset` is shared over: the MPI job's where it is shared, else this one alone.
inline const ProcessGroup& group_of(const data::Dataset& dataset) {
  return dataset.shared ? ProcessGroup::world() : ProcessGroup::alone();
}

}  // namespace lptn
