// A fleet dump: one subdirectory per motor, FLEET/<motor_id>/*.csv, of one motor type.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "hostio/process_group.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn::fleet {

struct FleetDump {
  // Every motor's cycles, named "<motor_id>/<cycle>", motor by motor; shared over the processes of
  // an MPI job by motor (load_shared_fleet).
  calibrate::SharedDataset dataset;
  std::vector<std::string> motor_ids;  // the subdirectories' names, sorted
  std::vector<std::vector<std::size_t>> motor_cycles;  // per motor: its cycles' indices in dataset
};

// Each subdirectory of `dir` is a motor (its *.csv files, as load_fleet_dump reads a directory);
// files beside them (motor.toml, truth.json) are left alone. Throws data::DataError naming `dir`
// when it holds no motor, and the first bad file as load_fleet_dump does.
FleetDump load_fleet(const std::filesystem::path& dir, const data::LoadOptions& options = {});

// The same fleet shared over the processes of an MPI job (trainer/calibrate/shared_dataset.hpp):
// each process loads only its own motors (motor m on rank m mod ranks); the other motors' cycles
// are remote. Alone, load_fleet.
FleetDump load_shared_fleet(const std::filesystem::path& dir, const hostio::ProcessGroup& group,
                            const data::LoadOptions& options = {});

}  // namespace lptn::fleet
