// lptn-td3: `lptn calibrate` with the TD3 calibrator (libtorch, trainer/td3/td3_method). lptn runs
// it for --method td3, td3-paper and td3-episode with the same arguments, so that libtorch is
// loaded only by the command that uses it.
#include "lptn/version.hpp"
#include "programs/cli/commands.hpp"
#include "trainer/td3/td3_method.hpp"

int main(int argc, char** argv) {
  CLI::App app{"lptn-td3: lptn calibrate with the TD3 calibrator (lptn runs it for --method td3|td3-paper|td3-episode)", "lptn-td3"};
  app.require_subcommand(1);
  app.set_version_flag("--version", lptn::kNameAndVersion);
  lptn::cli::add_calibrate(app, &lptn::td3::calibrate_td3);
  return lptn::cli::run_cli(app, argc, argv);
}
