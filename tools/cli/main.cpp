// lptn: the thermal estimator's command line. One program, one subcommand per user action.
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#include "tools/cli/commands.hpp"
#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/model/motor_file.hpp"
#if LPTN_WITH_TD3
#include "trainer/td3/td3_settings.hpp"
#endif

namespace {
// Bad input of any kind: one line naming what was wrong, exit code 2.
int bad_input(const std::exception& e) {
  std::fprintf(stderr, "lptn: error: %s\n", e.what());
  return 2;
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lptn: lumped-parameter thermal network estimator for traction motors"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "lptn 0.1.0");
  lptn::cli::add_generate(app);
  lptn::cli::add_inspect(app);
  lptn::cli::add_simulate(app);
  lptn::cli::add_calibrate(app);
  lptn::cli::add_diagnose(app);
  lptn::cli::add_export(app);
  lptn::cli::add_convert(app);
  lptn::cli::add_replay(app);
  lptn::cli::add_vcan_bench(app);
  lptn::cli::add_report(app);
  // CLI11 would only say that a subcommand is required; name the word it did not know.
  std::string known;
  bool is_known = false;
  for (const CLI::App* sub : app.get_subcommands({})) {
    known += (known.empty() ? "" : ", ") + sub->get_name();
    is_known = is_known || (argc > 1 && sub->get_name() == argv[1]);
  }
  if (argc > 1 && argv[1][0] != '-' && !is_known) {
    std::fprintf(stderr, "lptn: error: unknown subcommand '%s' (known: %s)\n", argv[1], known.c_str());
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "lptn: error: %s (see --help)\n", e.what());
    return 2;
  } catch (const lptn::data::DataError& e) {
    return bad_input(e);
  } catch (const lptn::MotorFileError& e) {
    return bad_input(e);
#if LPTN_WITH_TD3
  } catch (const lptn::td3::SettingsError& e) {
    return bad_input(e);
#endif
  } catch (const lptn::CalibrationFileError& e) {
    return bad_input(e);
  } catch (const lptn::cli::BadInput& e) {
    return bad_input(e);
  } catch (const std::invalid_argument& e) {
    return bad_input(e);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lptn: failed: %s\n", e.what());
    return 1;
  }
  return 0;
}
