#include "trainer/fleet/fleet_dump.hpp"

#include <algorithm>
#include <utility>

namespace lptn {

FleetDump load_fleet(const std::filesystem::path& dir, const data::LoadOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    throw data::DataError(dir.string() + ": not a directory (a fleet is FLEET/<motor_id>/*.csv)");
  std::vector<std::filesystem::path> motors;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.is_directory()) motors.push_back(e.path());
  if (motors.empty())
    throw data::DataError(dir.string() + ": no motor subdirectories (a fleet is FLEET/<motor_id>/*.csv)");
  std::sort(motors.begin(), motors.end());
  FleetDump fleet;
  for (const auto& path : motors) {
    data::Dataset one = data::load_fleet_dump({path}, options);
    const std::string id = path.filename().string();
    fleet.motor_ids.push_back(id);
    fleet.motor_cycles.emplace_back();
    for (data::Cycle& c : one.cycles) {
      c.name = id + "/" + c.name;
      fleet.motor_cycles.back().push_back(fleet.dataset.cycles.size());
      fleet.dataset.cycles.push_back(std::move(c));
    }
    for (data::CycleReport& r : one.reports) {
      r.name = id + "/" + r.name;
      fleet.dataset.reports.push_back(std::move(r));
    }
  }
  return fleet;
}

}  // namespace lptn
