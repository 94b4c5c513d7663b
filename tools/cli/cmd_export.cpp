// lptn export: a calibration as a C++ header that the firmware compiles in.
#include <cstdio>
#include <filesystem>
#include <string>

#include "tools/cli/commands.hpp"
#include "tools/export/export_header.hpp"
#include "trainer/calibrate/calibration_file.hpp"
#include "hostio/atomic_file.hpp"

namespace lptn::cli {

void add_export(CLI::App& app) {
  auto* cmd = app.add_subcommand("export", "Write a calibration as a C++ header for the firmware");
  struct Args {
    std::string calibration, out;
    bool actor = false, force = false;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("--calibration", args->calibration, "calibration.json (from lptn calibrate)")->required();
  cmd->add_option("--out", args->out, "Header to write, e.g. thermal_calibration.hpp")->required();
  cmd->add_flag("--actor", args->actor, "Also export the TD3 actor's weights (needs a calibration with an actor)");
  cmd->add_flag("--force", args->force, "Replace --out if it exists");
  cmd->callback([args] {
    // Checked before any work, so that a mistaken --out costs nothing and overwrites nothing.
    refuse_overwrite(args->out, args->force);
    try {
      const CalibrationResult calibration = load_calibration(args->calibration);
      ExportOptions options;
      options.source_name = std::filesystem::path(args->calibration).filename().string();
      options.actor = args->actor;
      write_file_atomically(args->out, export_header(calibration, options));
      std::printf("wrote %s (%s calibration of %s%s)\n", args->out.c_str(), calibration.method.c_str(),
                  calibration.motor_name.c_str(), args->actor ? ", with the actor" : "");
    } catch (const CalibrationFileError& e) {
      throw BadInput(e.what());
    } catch (const ExportError& e) {
      throw BadInput(e.what());
    }
  });
}

}  // namespace lptn::cli
