// lptn-full: the thermal estimator's command line, one subcommand per user action; lptn (main.cpp)
// runs it for every subcommand but replay and convert. libtorch is not in it: `lptn calibrate
// --method td3*` runs lptn-td3 (td3_main.cpp).
#include "lptn/version.hpp"
#include "programs/cli/commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{lptn::cli::kLptnDescription, "lptn"};
  app.require_subcommand(1);
  app.set_version_flag("--version", lptn::kNameAndVersion);
  lptn::cli::add_generate(app);
  lptn::cli::add_inspect(app);
  lptn::cli::add_simulate(app);
  lptn::cli::add_calibrate(app);
  lptn::cli::add_diagnose(app);
  lptn::cli::add_export(app);
  lptn::cli::add_convert(app);
  lptn::cli::add_replay(app);
  lptn::cli::add_report(app);
  lptn::cli::add_check(app);
  return lptn::cli::run_cli(app, argc, argv);
}
