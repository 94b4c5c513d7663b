// lptn export: a calibration as a C++ header that the firmware compiles in.
#include <cstdio>
#include <filesystem>
#include <string>

#include "programs/cli/commands.hpp"
#include "tools/export/export_header.hpp"
#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/fleet/fleet_file.hpp"
#include "hostio/atomic_file.hpp"

namespace lptn::cli {

void add_export(CLI::App& app) {
  auto* cmd = app.add_subcommand("export", "Write a calibration as a C++ header for the firmware");
  struct Args {
    std::string calibration, out, fleet, motor_id;
    bool actor = false, force = false;
  };
  auto args = std::make_shared<Args>();
  auto* calibration_option = cmd->add_option("--calibration", args->calibration, "calibration.json (from lptn calibrate)");
  auto* fleet = cmd->add_option("--fleet", args->fleet, "fleet.json (from lptn calibrate --fleet): one motor's header, with --motor-id");
  auto* motor_id = cmd->add_option("--motor-id", args->motor_id, "The fleet's motor to export (its subdirectory's name)");
  calibration_option->excludes(fleet);
  fleet->excludes(calibration_option);
  fleet->needs(motor_id);
  motor_id->needs(fleet);
  cmd->add_option("--out", args->out, "Header to write, e.g. thermal_calibration.hpp")->required();
  cmd->add_flag("--actor", args->actor, "Also export the TD3 actor's weights (needs a calibration with an actor)");
  cmd->add_flag("--force", args->force, "Replace --out if it exists");
  cmd->callback([args] {
    // Checked before any work, so that a mistaken --out costs nothing and overwrites nothing.
    if (args->calibration.empty() && args->fleet.empty())
      throw hostio::BadInput("export: give --calibration, or --fleet with --motor-id");
    if (!args->calibration.empty()) check_input_path(args->calibration, "--calibration", InputPath::file);
    if (!args->fleet.empty()) check_input_path(args->fleet, "--fleet", InputPath::file);
    check_output_path(args->out, args->force);
    const calibrate::CalibrationResult calibration = args->fleet.empty()
                                              ? calibrate::load_calibration(args->calibration)
                                              : fleet::motor_calibration(fleet::load_fleet_file(args->fleet), args->motor_id);
    exporter::ExportOptions options;
    options.source_name = std::filesystem::path(args->fleet.empty() ? args->calibration : args->fleet).filename().string();
    if (!args->fleet.empty()) options.source_name += ", motor " + args->motor_id;
    options.actor = args->actor;
    const std::string header = exporter::export_header(calibration, options);  // refuses a failed calibration
    // Each warning on a line of its own (the header carries them too, as comments).
    for (const calibrate::CalibrationWarning& w : calibration.warnings)
      std::fprintf(stderr, "lptn: warning: %s: %s\n", options.source_name.c_str(), w.message.c_str());
    hostio::write_file_atomically(args->out, header);
    std::printf("wrote %s (%s calibration of %s%s)\n", args->out.c_str(), calibration.method.c_str(),
                calibration.motor.name.c_str(), args->actor ? ", with the actor" : "");
  });
}

}  // namespace lptn::cli
