// --map data.toml, as every command that reads a dump takes it: the export's own columns, units,
// time and CSV dialect (docs/data-map.md). Without it each file is read through the data.toml beside
// it, if there is one.
#pragma once

#include <utility>
#include <string>

#include "programs/cli/commands.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn::cli {

inline void add_map_option(CLI::App* cmd, std::string& path) {
  cmd->add_option("--map", path,
                  "Data map (TOML): how to read an export's own column names, units, time column, separator and "
                  "drives (docs/data-map.md; lptn inspect --suggest-map proposes one). Default: data.toml beside the CSVs");
}

// `options` with the map of --map read in (a bad map: one line of bad input, through DataError).
inline data::LoadOptions with_map(const std::string& path, data::LoadOptions options = {}) {
  if (!path.empty()) check_input_path(path, "--map", InputPath::file);
  return data::with_data_map(path, std::move(options));
}

}  // namespace lptn::cli
