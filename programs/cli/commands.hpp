// Every `lptn` subcommand registers itself on the app here; each lives in its own cmd_*.cpp.
#pragma once

#include <CLI/CLI.hpp>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "hostio/bad_input.hpp"
#include "trainer/calibrate/calibration_request.hpp"

namespace lptn::cli {

void add_generate(CLI::App& app);
void add_inspect(CLI::App& app);
void add_simulate(CLI::App& app);
// `td3`: the TD3 calibrator where this program links it (lptn-td3); without one (lptn), --method
// td3|td3-episode runs lptn-td3 from beside this program with the same arguments.
void add_calibrate(CLI::App& app, calibrate::CalibrationMethod td3 = nullptr);
void add_diagnose(CLI::App& app);
void add_export(CLI::App& app);
void add_convert(CLI::App& app);
void add_replay(CLI::App& app);
void add_report(CLI::App& app);
void add_check(CLI::App& app);

// What `lptn --help` says first, in each program that is lptn (lptn, lptn-full).
inline constexpr char kLptnDescription[] = "lptn: lumped-parameter thermal network estimator for traction motors";

// The program's own arguments as main() received them, for handing a command over to another
// program (lptn calibrate --method td3 to lptn-td3).
std::vector<std::string>& invocation();

// Parses and runs `app` as every lptn program does: one line per failure, exit code 2 for bad input
// (BadInput, hostio/bad_input.hpp, which every module's own kind derives from; with the subcommand
// it did not know named), 1 for any other failure.
int parse_and_run(CLI::App& app, int argc, char** argv);
// parse_and_run, and in an MPI job a failure ends every rank (MPI linked: lptn-full, lptn-td3).
int run_cli(CLI::App& app, int argc, char** argv);


// An output that is there already is replaced only with --force (empty: no such output asked for).
inline void refuse_overwrite(const std::string& path, bool force) {
  if (!path.empty() && !force && std::filesystem::exists(path))
    throw hostio::BadInput(path + ": exists (use --force to replace it)");
}

// What an input path must be, for check_input_path.
enum class InputPath { file, directory, file_or_directory };

// An input that is not there is said at once, before any output is checked or work done:
// "--data nosuch: no such file or directory", "--motor m.toml: is a directory, not a file".
inline void check_input_path(const std::string& path, std::string_view option,
                             InputPath kind = InputPath::file_or_directory) {
  namespace fs = std::filesystem;
  const std::string what = std::string(option) + " " + path + ": ";
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) {
    throw hostio::BadInput(what + (kind == InputPath::file        ? "no such file"
                           : kind == InputPath::directory ? "no such directory"
                                                          : "no such file or directory"));
  }
  if (kind == InputPath::file && fs::is_directory(status)) throw hostio::BadInput(what + "is a directory, not a file");
  if (kind == InputPath::directory && !fs::is_directory(status)) throw hostio::BadInput(what + "is not a directory");
  if (::access(path.c_str(), R_OK) != 0) throw hostio::BadInput(what + "cannot be read (permission denied)");
}

// An output path checked before any work, so that a long run does not end in "cannot write":
// its directory must exist and be writable ("--out nosuchdir/x.json: directory 'nosuchdir' does
// not exist"), and the output must not exist without --force (refuse_overwrite's message; an
// empty directory is no output yet, as AtomicDirectory takes it). Call it after check_input_path
// on the inputs: a missing input is the first thing to hear of.
inline void check_output_path(const std::string& path, bool force, std::string_view option = "--out") {
  namespace fs = std::filesystem;
  if (path.empty()) return;
  fs::path target(path);
  if (target.filename().empty()) target = target.parent_path();  // "out/" names the directory out
  const fs::path dir = target.parent_path();
  const std::string shown = dir.empty() ? "." : dir.string();
  const std::string what = std::string(option) + " " + path + ": directory '" + shown + "' ";
  std::error_code ec;
  if (!dir.empty() && !fs::exists(dir, ec)) throw hostio::BadInput(what + "does not exist");
  if (!dir.empty() && !fs::is_directory(dir, ec)) throw hostio::BadInput(what + "is not a directory");
  if (::access(shown.c_str(), W_OK | X_OK) != 0) throw hostio::BadInput(what + "is not writable");
  if (fs::exists(target, ec) && !(fs::is_directory(target, ec) && fs::is_empty(target, ec)))
    refuse_overwrite(path, force);
}

// Warnings about the input that a command repeats before its results (data::inspection_warnings,
// input_warnings in trainer/model/motor_plausibility.hpp), one line each on stderr; past
// `at_most`, one line with how many more (lptn inspect lists them all).
inline void print_input_warnings(const std::vector<std::string>& warnings, std::size_t at_most = 20) {
  for (std::size_t i = 0; i < warnings.size() && i < at_most; ++i)
    std::fprintf(stderr, "lptn: warning: %s\n", warnings[i].c_str());
  if (warnings.size() > at_most)
    std::fprintf(stderr, "lptn: warning: and %zu more (lptn inspect lists every one)\n", warnings.size() - at_most);
}

}  // namespace lptn::cli
