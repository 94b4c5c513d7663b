// Runs the built `lptn` (LPTN_BINARY) with arguments, as a user's shell would, and keeps what it said.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace lptn::testing {

struct Result {
  int code;
  std::string out;  // stdout
  std::string err;  // stderr
};

// stdout and stderr go to files in `scratch`.
inline Result run(const std::string& args, const std::filesystem::path& scratch) {
  const auto out = scratch / "stdout.txt", err = scratch / "stderr.txt";
  const std::string cmd = std::string(LPTN_BINARY) + " " + args + " >" + out.string() + " 2>" + err.string();
  const int status = std::system(cmd.c_str());
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

// One cycle of `lptn generate` (its seed, between minutes_min and minutes_max long) in scratch/data:
// what generate said, and the cycle's CSV (empty if it wrote none; the caller asserts both).
struct GeneratedCycle {
  Result generate;
  std::filesystem::path csv;
};
inline GeneratedCycle generate_cycle(const std::filesystem::path& scratch, int seed, int minutes_min, int minutes_max) {
  GeneratedCycle g;
  const std::filesystem::path data = scratch / "data";
  g.generate = run("generate --out " + data.string() + " --cycles 1 --seed " + std::to_string(seed) + " --minutes-min " +
                       std::to_string(minutes_min) + " --minutes-max " + std::to_string(minutes_max),
                   scratch);
  if (g.generate.code != 0) return g;
  for (const auto& e : std::filesystem::directory_iterator(data))
    if (e.path().extension() == ".csv") g.csv = e.path();
  return g;
}

}  // namespace lptn::testing
