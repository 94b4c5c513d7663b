// lptn: the thermal estimator's command line. The program a user runs, for every subcommand.
// Replaying and converting logs (and --version) run here, in a program that links none of the
// calibrators' libraries: lptn-full, the program of every subcommand, loads Ceres, OpenBLAS,
// LAPACK and Open MPI (and starts OpenBLAS's threads) before main(), 6 ms of a 0.1 s replay of a
// 1.5 h log (docs/benchmarks.md). Every other subcommand, and --help, is handed over to lptn-full,
// installed beside lptn, with this very command line.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>

#include "lptn/version.hpp"
#include "programs/cli/commands.hpp"

namespace {

bool runs_here(int argc, char** argv) {
  if (argc < 2) return false;
  const std::string_view first = argv[1];
  return first == "replay" || first == "convert" || first == "--version";
}

// Returns only if lptn-full could not be started.
int hand_over_to_full_program(char** argv) {
  char self[4096];
  const ssize_t length = ::readlink("/proc/self/exe", self, sizeof self - 1);
  std::string program = length > 0 ? std::string(self, static_cast<std::size_t>(length)) : std::string(argv[0]);
  program = program.substr(0, program.rfind('/') + 1) + "lptn-full";
  std::fflush(stdout);
  ::execv(program.c_str(), argv);  // argv[0] stays the user's: lptn-full finds lptn-td3 by /proc/self/exe
  std::fprintf(stderr, "lptn: error: %s: cannot run it (%s); lptn-full is installed beside lptn\n", program.c_str(),
               std::strerror(errno));
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (!runs_here(argc, argv)) return hand_over_to_full_program(argv);
  CLI::App app{lptn::cli::kLptnDescription, "lptn"};
  app.require_subcommand(1);
  app.set_version_flag("--version", lptn::kNameAndVersion);
  lptn::cli::add_convert(app);
  lptn::cli::add_replay(app);
  return lptn::cli::parse_and_run(app, argc, argv);
}
