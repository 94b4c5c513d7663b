// Every `lptn` subcommand registers itself on the app here; each lives in its own cmd_*.cpp.
#pragma once

#include <CLI/CLI.hpp>

#include <filesystem>
#include <stdexcept>
#include <string>

namespace lptn::cli {

void add_generate(CLI::App& app);
void add_inspect(CLI::App& app);
void add_simulate(CLI::App& app);
void add_calibrate(CLI::App& app);
void add_diagnose(CLI::App& app);
void add_export(CLI::App& app);
void add_convert(CLI::App& app);
void add_replay(CLI::App& app);
void add_vcan_bench(CLI::App& app);
void add_report(CLI::App& app);

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
