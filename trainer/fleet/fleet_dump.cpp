#include "trainer/fleet/fleet_dump.hpp"

#include <algorithm>
#include <utility>

#include "trainer/calibrate/shared_dataset.hpp"

namespace lptn::fleet {
namespace {

std::vector<std::filesystem::path> motor_directories(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    throw data::DataError(dir.string() + ": not a directory (a fleet is FLEET/<motor_id>/*.csv)");
  std::vector<std::filesystem::path> motors;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.is_directory()) motors.push_back(e.path());
  if (motors.empty())
    throw data::DataError(dir.string() + ": no motor subdirectories (a fleet is FLEET/<motor_id>/*.csv)");
  std::sort(motors.begin(), motors.end());
  return motors;
}

// One motor's files, its cycles and reports named "<motor_id>/<cycle>".
data::Dataset load_motor(const std::filesystem::path& path, const data::LoadOptions& options) {
  data::Dataset one = data::load_fleet_dump({path}, options);
  const std::string id = path.filename().string();
  for (data::Cycle& c : one.cycles) c.name = id + "/" + c.name;
  for (data::CycleReport& r : one.reports) r.name = id + "/" + r.name;
  return one;
}

}  // namespace

FleetDump load_fleet(const std::filesystem::path& dir, const data::LoadOptions& options) {
  return load_shared_fleet(dir, hostio::ProcessGroup::alone(), options);
}

FleetDump load_shared_fleet(const std::filesystem::path& dir, const hostio::ProcessGroup& group,
                            const data::LoadOptions& options) {
  const std::vector<std::filesystem::path> motors = motor_directories(dir);
  std::vector<calibrate::LoadedUnit> mine;
  for (std::size_t m = 0; m < motors.size(); ++m)
    if (calibrate::owner_of_unit(m, group) == group.rank()) mine.push_back({m, load_motor(motors[m], options)});
  FleetDump fleet;
  for (const auto& path : motors) fleet.motor_ids.push_back(path.filename().string());
  fleet.motor_cycles.resize(motors.size());
  std::vector<std::size_t> motor_of;
  if (group.shared()) {
    fleet.dataset = calibrate::join_units(motors.size(), std::move(mine), group, &motor_of);
  } else {
    for (calibrate::LoadedUnit& u : mine) {
      for (data::Cycle& c : u.data.cycles) {
        fleet.dataset.data.cycles.push_back(std::move(c));
        motor_of.push_back(u.unit);
      }
      for (data::CycleReport& r : u.data.reports) fleet.dataset.data.reports.push_back(std::move(r));
    }
  }
  for (std::size_t c = 0; c < motor_of.size(); ++c) fleet.motor_cycles[motor_of[c]].push_back(c);
  return fleet;
}

}  // namespace lptn::fleet
