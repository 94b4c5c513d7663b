#pragma once
// A data map proposed for an unknown export (lptn inspect --suggest-map): the CSV dialect detected,
// the time column parsed, each of lptn's channels matched to a column by its name and by the range
// of its values, one long file's drives found. What it could not decide is said, not guessed quietly.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "trainer/data/data_map.hpp"

namespace lptn::data {

// What the motor file says that helps tell columns apart; zeros where unknown.
struct SuggestHints {
  int pole_pairs = 0;
  double rated_current_a = 0, rated_voltage_v = 0, nominal_airflow_m3s = 0;
};

struct MapSuggestion {
  DataMap map;
  // For each mapped column, why ("n_Motor -> speed_rpm in rpm: by its name; 30.0 x f_Stator").
  std::vector<std::string> evidence;
  // What the user must look at: a required channel without a column, a guessed unit, files whose
  // headers differ. Empty when the map is complete.
  std::vector<std::string> problems;
  // The map as data.toml text, the evidence and problems as comments on top.
  std::string text() const;
};

// `paths` as lptn's commands take them (directories of *.csv, or files). Reads the first file's
// first few megabytes for the values; every file's header. Throws DataError when there is no file.
MapSuggestion suggest_data_map(const std::vector<std::filesystem::path>& paths, const SuggestHints& hints = {});

// The same for one file's text already in memory; `file` is only used for names and messages.
MapSuggestion suggest_data_map_text(std::string_view text, const std::filesystem::path& file,
                                    const SuggestHints& hints = {});

}  // namespace lptn::data
