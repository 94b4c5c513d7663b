#include "trainer/calibrate/shared_dataset.hpp"

#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <utility>

#include "trainer/calibrate/calibration_file.hpp"  // sha256_file
#include "trainer/calibrate/grid_residuals.hpp"

namespace lptn {

data::Dataset join_units(std::size_t units, std::vector<LoadedUnit> mine, const ProcessGroup& group,
                         std::vector<std::size_t>* unit_of_cycle) {
  // What the other ranks learn of each of this rank's cycles (doubles survive JSON exactly).
  nlohmann::json stubs = nlohmann::json::array();
  for (LoadedUnit& u : mine) {
    if (owner_of_unit(u.unit, group) != group.rank())
      throw std::logic_error("join_units: unit " + std::to_string(u.unit) + " is not this rank's");
    std::map<std::string, std::string> hashes;
    for (data::Cycle& c : u.data.cycles) {
      const std::string file = c.file.string();
      if (!hashes.count(file)) hashes[file] = sha256_file(c.file);
      c.file_sha256 = hashes[file];
      stubs.push_back({{"unit", u.unit}, {"name", c.name}, {"file", file}, {"t0", c.t0_s}, {"dt", c.dt_s},
                       {"steps", c.steps}, {"residuals", count_grid_residuals(c)}, {"sha256", c.file_sha256}});
    }
  }
  std::vector<std::vector<data::Cycle>> per_unit(units);
  std::vector<bool> local(units, false);
  data::Dataset out;
  for (LoadedUnit& u : mine) {
    local[u.unit] = true;
    per_unit[u.unit] = std::move(u.data.cycles);
    for (data::CycleReport& r : u.data.reports) out.reports.push_back(std::move(r));
  }
  for (const std::string& text : group.gather(stubs.dump())) {
    for (const nlohmann::json& s : nlohmann::json::parse(text)) {
      const auto unit = s.at("unit").get<std::size_t>();
      if (unit >= units) throw std::logic_error("join_units: a rank sent unit " + std::to_string(unit));
      if (local[unit]) continue;
      data::Cycle c;
      c.remote = true;
      c.name = s.at("name").get<std::string>();
      c.file = s.at("file").get<std::string>();
      c.t0_s = s.at("t0").get<double>();
      c.dt_s = s.at("dt").get<double>();
      c.steps = s.at("steps").get<std::size_t>();
      c.remote_residuals = s.at("residuals").get<std::size_t>();
      c.file_sha256 = s.at("sha256").get<std::string>();
      per_unit[unit].push_back(std::move(c));
    }
  }
  out.shared = group.shared();
  if (unit_of_cycle != nullptr) unit_of_cycle->clear();
  for (std::size_t u = 0; u < units; ++u)
    for (data::Cycle& c : per_unit[u]) {
      out.cycles.push_back(std::move(c));
      if (unit_of_cycle != nullptr) unit_of_cycle->push_back(u);
    }
  return out;
}

void share_work(data::Dataset& dataset, const ProcessGroup& group) {
  if (!group.shared()) return;
  for (std::size_t i = 0; i < dataset.cycles.size(); ++i) {
    data::Cycle& c = dataset.cycles[i];
    if (owner_of_unit(i, group) == group.rank()) continue;
    c.remote_residuals = count_grid_residuals(c);
    c.remote = true;  // its samples stay: only the shared computations leave it to its rank
  }
  dataset.shared = true;
}

data::Dataset load_shared_dump(const std::vector<std::filesystem::path>& paths, const ProcessGroup& group,
                               const data::LoadOptions& options) {
  if (!group.shared()) return data::load_fleet_dump(paths, options);
  const std::vector<std::filesystem::path> files = data::cycle_files(paths);
  std::vector<std::filesystem::path> own;
  for (std::size_t f = 0; f < files.size(); ++f)
    if (owner_of_unit(f, group) == group.rank()) own.push_back(files[f]);
  // This rank's files on its cores, then back to their units: a file's cycles name it.
  data::Dataset loaded = own.empty() ? data::Dataset{} : data::load_fleet_dump(own, options);
  std::vector<LoadedUnit> mine;
  for (std::size_t f = 0; f < files.size(); ++f) {
    if (owner_of_unit(f, group) != group.rank()) continue;
    LoadedUnit u;
    u.unit = f;
    for (data::Cycle& c : loaded.cycles)
      if (c.file == files[f]) u.data.cycles.push_back(std::move(c));
    for (data::CycleReport& r : loaded.reports)
      if (r.file == files[f]) u.data.reports.push_back(std::move(r));
    mine.push_back(std::move(u));
  }
  return join_units(files.size(), std::move(mine), group);
}

}  // namespace lptn
