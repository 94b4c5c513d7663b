// A CSV (lptn replay's estimates, a fleet-dump cycle) as columns of numbers by header name; an
// empty cell is NaN. For tests that read what the CLI wrote.
#pragma once

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace lptn::testing {

inline std::map<std::string, std::vector<double>> read_csv_columns(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string cell; std::getline(header, cell, ',');) names.push_back(cell);
  std::map<std::string, std::vector<double>> cols;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::size_t i = 0;
    for (std::string cell; i < names.size(); ++i) {
      if (!std::getline(row, cell, ',')) cell.clear();
      cols[names[i]].push_back(cell.empty() ? NAN : std::stod(cell));
    }
  }
  return cols;
}

}  // namespace lptn::testing
