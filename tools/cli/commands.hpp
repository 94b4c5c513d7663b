// Every `lptn` subcommand registers itself on the app here; each lives in its own cmd_*.cpp.
#pragma once

#include <CLI/CLI.hpp>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "tools/cli/calibrate_args.hpp"

namespace lptn::cli {

void add_generate(CLI::App& app);
void add_inspect(CLI::App& app);
void add_simulate(CLI::App& app);
// `td3`: the TD3 calibrator where this program links it (lptn-td3); without one (lptn), --method
// td3|td3-episode runs lptn-td3 from beside this program with the same arguments.
void add_calibrate(CLI::App& app, Td3Calibrator td3 = nullptr);
void add_diagnose(CLI::App& app);
void add_export(CLI::App& app);
void add_convert(CLI::App& app);
void add_replay(CLI::App& app);
void add_report(CLI::App& app);
void add_check(CLI::App& app);

// The program's own arguments as main() received them, for handing a command over to another
// program (lptn calibrate --method td3 to lptn-td3).
std::vector<std::string>& invocation();

// Parses and runs `app` as every lptn program does: one line per failure, exit code 2 for bad input
// (with the subcommand it did not know named), 1 for any other failure.
int run_cli(CLI::App& app, int argc, char** argv);

// A bad-input failure: reported as one line, exit code 2.
struct BadInput : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// An output that is there already is replaced only with --force (empty: no such output asked for).
inline void refuse_overwrite(const std::string& path, bool force) {
  if (!path.empty() && !force && std::filesystem::exists(path))
    throw BadInput(path + ": exists (use --force to replace it)");
}

}  // namespace lptn::cli
