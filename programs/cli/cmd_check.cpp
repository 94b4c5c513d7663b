// lptn check: does a calibration still hold on this data (trainer/check/)? Exit 0 it holds, 1 it
// does not, 2 bad input: a fleet pipeline scripts on the code.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "hostio/atomic_file.hpp"
#include "hostio/process_group.hpp"
#include "hostio/progress_line.hpp"
#include "hostio/worker_threads.hpp"
#include "programs/cli/commands.hpp"
#include "programs/cli/data_map_option.hpp"
#include "programs/cli/exit_code.hpp"
#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/calibrate/calibration_outcome.hpp"
#include "trainer/check/check.hpp"
#include "trainer/check/sensor_corrections.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/fleet/fleet_dump.hpp"
#include "trainer/fleet/fleet_file.hpp"

namespace lptn::cli {
namespace {

struct CheckArgs {
  std::vector<std::string> data;
  std::string fleet, calibration, json_out, map;
  bool json = false, force = false, quiet = false;
};

bool is_fleet_file(const std::string& path) {
  const nlohmann::json j = calibrate::read_lptn_json(path);
  return j.is_object() && j.contains("pooled") && j.contains("motors");
}

// One motor's cycles as a dataset of their own (names stay "<motor_id>/<cycle>", as fleet.json's
// data lists them); the loader's reports come along for the sensors' reading periods.
data::Dataset motor_dataset(const fleet::FleetDump& fleet, std::size_t m) {
  data::Dataset d;
  for (std::size_t i : fleet.motor_cycles[m]) d.cycles.push_back(fleet.dataset.data.cycles[i]);
  d.reports = fleet.dataset.data.reports;
  return d;
}

bool check_data(const CheckArgs& a) {
  if (is_fleet_file(a.calibration))
    throw hostio::BadInput(a.calibration + ": a fleet calibration (lptn calibrate --fleet): use --fleet FLEET, each motor against "
                                   "its own cooling factor");
  const calibrate::CalibrationResult calibration = calibrate::load_calibration(a.calibration);
  if (const std::string caution = calibrate::status_caution(calibration, a.calibration, false); !caution.empty())
    std::fprintf(stderr, "lptn: warning: %s\n", caution.c_str());
  const std::vector<std::filesystem::path> paths(a.data.begin(), a.data.end());
  data::Dataset dataset = data::load_fleet_dump(paths, with_map(a.map));
  const std::vector<std::string> corrections = check::correct_as_calibrated(dataset, calibration);
  if (!a.json)
    for (const std::string& note : corrections) std::printf("%s\n", note.c_str());
  check::Check c;
  {
    hostio::ProgressLine line(a.quiet || a.json);
    line.update("check: " + std::to_string(dataset.cycles.size()) + " cycles", true);
    c = check::check(calibration, dataset, check::motor_beside(a.data), hostio::worker_threads());
  }
  nlohmann::json j = check::to_json(c);
  j["calibration"] = a.calibration;
  j["data"]["paths"] = a.data;
  if (!a.json_out.empty()) hostio::write_file_atomically(a.json_out, j.dump(2) + "\n");
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("checking %s (%s, %s, motor %s) on %zu cycles\n", a.calibration.c_str(), calibration.method.c_str(),
                calibration.created_utc.c_str(), calibration.motor.name.c_str(), dataset.cycles.size());
    std::printf("%s", check::describe(c).c_str());
  }
  return c.holds;
}

// One motor checked: with fleet.json against the type and its own cooling factor; a motor the
// fleet calibration does not know, and every motor under a calibration.json, against that calibration.
nlohmann::json check_motor(const CheckArgs& a, const std::optional<fleet::FleetFile>& fleet_file, const calibrate::CalibrationResult& single,
                           const fleet::FleetDump& fleet, std::size_t m, const std::optional<MotorFile>& data_motor) {
  const std::string& id = fleet.motor_ids[m];
  std::string against = fleet_file ? "the type (not in " + a.calibration + ")" : a.calibration;
  calibrate::CalibrationResult calibration = single;
  if (fleet_file) {
    calibration = fleet_file->pooled;
    for (const fleet::FleetFileMotor& fm : fleet_file->motors)
      if (fm.id == id) {
        calibration = fleet::motor_calibration(*fleet_file, id);
        char factor[96];
        std::snprintf(factor, sizeof factor, "the type with its own cooling factor %.3f", fm.cooling_factor);
        against = factor;
      }
  }
  const check::Check c = check::check(calibration, motor_dataset(fleet, m), data_motor, hostio::worker_threads());
  nlohmann::json j = check::to_json(c);
  j["motor_id"] = id;
  j["against"] = against;
  return j;
}

// Under mpirun the motors are shared over the processes (motor m loaded and checked by the rank
// that load_shared_fleet gives it); every rank joins the verdicts, rank 0 prints and writes.
bool check_fleet(const CheckArgs& given) {
  const hostio::ProcessGroup& group = hostio::ProcessGroup::world();
  CheckArgs a = given;
  if (!group.leads()) {
    a.quiet = true;
    if (std::freopen("/dev/null", "w", stdout) == nullptr) throw std::runtime_error("cannot silence rank " + std::to_string(group.rank()));
  }
  std::optional<fleet::FleetFile> fleet_file;
  calibrate::CalibrationResult single;
  if (is_fleet_file(a.calibration)) fleet_file = fleet::load_fleet_file(a.calibration);
  else single = calibrate::load_calibration(a.calibration);
  const fleet::FleetDump fleet = fleet::load_shared_fleet(a.fleet, group, with_map(a.map));
  const std::optional<MotorFile> data_motor = check::motor_beside({a.fleet});
  nlohmann::json mine = nlohmann::json::object();  // motor index -> its verdict, for this rank's motors
  {
    hostio::ProgressLine line(a.quiet || a.json);
    for (std::size_t m = 0; m < fleet.motor_ids.size(); ++m) {
      const auto& cycles = fleet.motor_cycles[m];
      if (cycles.empty() || calibrate::DatasetRef(fleet.dataset).remote(cycles.front())) continue;  // another rank's
      line.update("check: " + fleet.motor_ids[m] + " (" + std::to_string(m + 1) + "/" +
                  std::to_string(fleet.motor_ids.size()) + ")", true);
      mine[std::to_string(m)] = check_motor(a, fleet_file, single, fleet, m, data_motor);
    }
  }
  nlohmann::json by_motor = nlohmann::json::object();
  for (const std::string& part : group.shared() ? group.gather(mine.dump()) : std::vector<std::string>{mine.dump()})
    by_motor.update(nlohmann::json::parse(part));

  nlohmann::json motors = nlohmann::json::array();
  std::vector<std::string> failing, reasons;
  for (std::size_t m = 0; m < fleet.motor_ids.size(); ++m) {
    if (!by_motor.contains(std::to_string(m))) continue;  // a motor directory without cycles
    const nlohmann::json& j = by_motor[std::to_string(m)];
    motors.push_back(j);
    const std::string id = j["motor_id"];
    if (!j["holds"].get<bool>()) {
      failing.push_back(id);
      for (const std::string r : j["reasons"]) reasons.push_back(id + ": " + r);
    }
    if (a.json) continue;
    std::printf("%s (against %s): %s\n", id.c_str(), j["against"].get<std::string>().c_str(),
                j["holds"].get<bool>() ? "holds" : "does NOT hold");
    for (const std::string r : j["reasons"]) std::printf("  %s\n", r.c_str());
    if (const std::string seen = j["data"]["summary"]; !seen.empty())
      std::printf("  data this calibration never saw: %s\n", seen.c_str());
  }
  nlohmann::json j = {{"holds", failing.empty()}, {"reasons", reasons}, {"not_holding", failing},
                      {"calibration", a.calibration}, {"fleet", a.fleet}, {"motors", motors}};
  if (!a.json_out.empty() && group.leads()) hostio::write_file_atomically(a.json_out, j.dump(2) + "\n");
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else if (failing.empty()) {
    std::printf("every motor's calibration holds (%zu motors)\n", motors.size());
  } else {
    std::string list;
    for (const std::string& id : failing) list += (list.empty() ? "" : ", ") + id;
    std::printf("%zu of %zu motors' calibration no longer holds: %s\n", failing.size(), motors.size(), list.c_str());
  }
  return failing.empty();
}

void run(const CheckArgs& a) {
  if (a.data.empty() == a.fleet.empty()) throw hostio::BadInput("check: give --data DIR or --fleet FLEET (one of them)");
  // Inputs, then the output, before any work (a missing input is the first thing to hear of).
  for (const std::string& d : a.data) check_input_path(d, "--data");
  if (!a.fleet.empty()) check_input_path(a.fleet, "--fleet", InputPath::directory);
  check_input_path(a.calibration, "--calibration", InputPath::file);
  check_output_path(a.json_out, a.force, "--json-out");
  if (!std::filesystem::is_regular_file(a.calibration)) throw hostio::BadInput(a.calibration + ": no such file");
  if (!a.fleet.empty() && !std::filesystem::is_directory(a.fleet)) throw hostio::BadInput(a.fleet + ": no such directory");
  if (a.fleet.empty() && hostio::ProcessGroup::world().shared())
    throw hostio::BadInput("check --data under mpirun: one dump is checked by one process (--fleet shares its motors)");
  // "Does not hold" is an answer, not a failure: run_cli returns the code once the command returned.
  const bool holds = a.fleet.empty() ? check_data(a) : check_fleet(a);
  if (!holds) set_exit_code(kExitDoesNotHold);
}

}  // namespace

void add_check(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "check", "Does a calibration still hold on this data? Each cycle's error against its sensors' noise and the "
               "calibration's own test error, and its cooling factor against the calibration's; exit 0 it holds, 1 it "
               "does not, 2 bad input (docs/check.md); with --fleet under `mpirun -np N` the motors are shared over N "
               "processes");
  auto a = std::make_shared<CheckArgs>();
  cmd->add_option("--data", a->data, "Directories of cycle CSVs, or CSV files: the data to check the calibration on")
      ->expected(1, -1);
  cmd->add_option("--fleet", a->fleet,
                  "A fleet dump (FLEET/<motor_id>/): every motor checked, against its own cooling factor with a fleet.json");
  cmd->add_option("--calibration", a->calibration, "calibration.json (lptn calibrate), or fleet.json with --fleet")->required();
  add_map_option(cmd, a->map);
  cmd->add_flag("--json", a->json, "Print the verdict as JSON: {\"holds\", \"reasons\", \"sensors\", \"cycles\": [...]}");
  cmd->add_option("--json-out", a->json_out, "Also write that JSON to this file");
  cmd->add_flag("--force", a->force, "Replace --json-out if it exists");
  cmd->add_flag("--quiet", a->quiet, "No progress output");
  cmd->callback([a] { run(*a); });
}

}  // namespace lptn::cli
