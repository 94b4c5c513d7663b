// The lptn program as a user meets it: --help everywhere, one-line errors with non-zero exits,
// nothing half-written, and generate's output passing inspect without warnings.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "lptn_testing/run_lptn.hpp"
#include "lptn_testing/temp_dir.hpp"

namespace lptn::cli {
namespace {

using testing::Result;
using testing::run;

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

TEST(Cli, EverySubcommandHasHelp) {
  testing::TempDir t;
  for (const char* sub : {"generate", "inspect", "simulate", "calibrate", "export", "convert", "replay"}) {
    const Result r = run(std::string(sub) + " --help", t.path());
    EXPECT_EQ(r.code, 0) << sub;
    EXPECT_NE(r.out.find("--"), std::string::npos) << sub;
  }
  EXPECT_EQ(run("--help", t.path()).code, 0);
}

// The libraries a command's process loads, as the dynamic loader lists them (LD_DEBUG=files: one
// "file=NAME [0];  needed by ..." line each, for lptn and, after the hand-over, lptn-full).
std::string loaded_libraries(const std::string& args, const std::filesystem::path& scratch) {
  const auto err = scratch / "loader.txt";
  const std::string cmd = "LD_DEBUG=files " + std::string(LPTN_BINARY) + " " + args + " >/dev/null 2>" + err.string();
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream in(err);
  std::string names, line;
  while (std::getline(in, line))
    if (const auto at = line.find("file="); at != std::string::npos && line.find("needed by") != std::string::npos)
      names += line.substr(at + 5, line.find(' ', at) - at - 5) + " ";
  return names;
}

// Replay and convert run in lptn itself, which loads none of the calibrators' libraries (their
// loading and OpenBLAS's threads were 6 ms of a 0.1 s replay); any other command is lptn-full's,
// and loads them.
TEST(Cli, ReplayAndConvertLoadNoneOfTheCalibratorsLibraries) {
  testing::TempDir t;
  for (const char* command : {"replay --help", "convert --help", "--version"}) {
    const std::string libraries = loaded_libraries(command, t.path());
    EXPECT_NE(libraries.find("libstdc++"), std::string::npos) << command << ": " << libraries;  // the list is read
    for (const char* heavy : {"libmpi", "libopen-pal", "libceres", "libglog", "libopenblas", "libblas", "liblapack",
                              "libcholmod", "libgfortran", "libtorch"})
      EXPECT_EQ(libraries.find(heavy), std::string::npos) << command << " loads " << heavy << ": " << libraries;
  }
  // Handed over: the same list shows them.
  const std::string full = loaded_libraries("calibrate --help", t.path());
  EXPECT_NE(full.find("liblapack"), std::string::npos) << full;
}

// lptn copied somewhere without lptn-full (a user who takes the one program): replay still runs
// there, and any other command ends at once with one line naming what is missing, not in silence.
TEST(Cli, WithoutLptnFullBesideItACommandSaysSo) {
  testing::TempDir t;
  const auto alone = t.path() / "lptn";
  std::filesystem::copy_file(LPTN_BINARY, alone);
  const auto err = t.path() / "err.txt";
  const int status = std::system((alone.string() + " inspect --help >/dev/null 2>" + err.string()).c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  std::ifstream in(err);
  const std::string said((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(lines(said), 1) << said;
  EXPECT_NE(said.find((t.path() / "lptn-full").string() + ": cannot run it"), std::string::npos) << said;
  EXPECT_EQ(std::system((alone.string() + " replay --help >/dev/null 2>&1").c_str()), 0);
}

TEST(Cli, GeneratedDataPassesInspectWithoutWarnings) {
  testing::TempDir t;
  const auto data = t.path() / "fleet";
  const Result g = run("generate --out " + data.string() + " --cycles 3 --seed 2 --minutes-min 20 --minutes-max 25", t.path());
  ASSERT_EQ(g.code, 0) << g.err;
  EXPECT_NE(g.out.find(data.string()), std::string::npos);  // says where the output went
  EXPECT_EQ(lines(g.err), 3);                               // one progress line a cycle
  const Result i = run("inspect --data " + data.string() + " --motor " + (data / "motor.toml").string() + " --json", t.path());
  ASSERT_EQ(i.code, 0) << i.err;
  const auto report = nlohmann::json::parse(i.out);
  EXPECT_EQ(report["warnings"], 0);
  EXPECT_EQ(report["cycles"].size(), 3u);
  EXPECT_EQ(run("inspect --strict --data " + data.string(), t.path()).code, 0);
}

TEST(Cli, SimulateComparesAndWritesTraces) {
  testing::TempDir t;
  const auto data = t.path() / "fleet";
  ASSERT_EQ(run("generate --out " + data.string() + " --cycles 2 --seed 2 --minutes-min 15 --minutes-max 15", t.path()).code, 0);
  const auto traces = t.path() / "traces";
  const Result s = run("simulate --json --data " + data.string() + " --motor " + (data / "motor.toml").string() +
                           " --set lambda_1s=24 --set lambda_2s=65 --set lambda_12s=110 --set lambda_1r=21 "
                           "--set lambda_2r=45 --set lambda_12r=150 --out " + traces.string(),
                       t.path());
  ASSERT_EQ(s.code, 0) << s.err;
  const auto j = nlohmann::json::parse(s.out);
  // The true parameters reproduce the plant to about the sensor noise (0.4 K).
  EXPECT_LT(j["overall"]["stator"]["rmse_k"].get<double>(), 0.6);
  EXPECT_GT(j["overall"]["stator"]["rmse_k"].get<double>(), 0.3);
  EXPECT_TRUE(std::filesystem::exists(traces / "metrics.json"));
  EXPECT_TRUE(std::filesystem::exists(traces / "cycle_01_suburban.csv"));
  // The motor file's initial guesses do not.
  const Result guess = run("simulate --json --data " + data.string() + " --motor " + (data / "motor.toml").string(), t.path());
  EXPECT_GT(nlohmann::json::parse(guess.out)["overall"]["stator"]["rmse_k"].get<double>(), 3.0);
}

TEST(Cli, BadInputGivesOneLineAndANonZeroExitAndNoOutput) {
  testing::TempDir t;
  const auto data = t.path() / "fleet";
  ASSERT_EQ(run("generate --out " + data.string() + " --cycles 1 --seed 2 --minutes-min 10 --minutes-max 10", t.path()).code, 0);
  // A cycle file with a non-numeric cell on line 3.
  {
    std::ifstream in(data / "cycle_01_suburban.csv");
    std::ofstream bad(t.path() / "bad.csv");
    std::string line;
    for (int n = 1; std::getline(in, line) && n <= 50; ++n) bad << (n == 3 ? line.replace(line.find(','), 1, ",x") : line) << '\n';
  }
  struct Case {
    std::string args, must_name;
  };
  const Case cases[] = {
      {"inspect --data " + (t.path() / "bad.csv").string(), "bad.csv:3:"},
      {"inspect --data " + (t.path() / "nowhere").string(), "nowhere"},
      {"simulate --data " + data.string() + " --motor " + (t.path() / "missing.toml").string() + " --out " + (t.path() / "o1").string(), "missing.toml"},
      {"simulate --data " + (t.path() / "bad.csv").string() + " --motor " + (data / "motor.toml").string() + " --out " + (t.path() / "o2").string(), "bad.csv:3:"},
      {"simulate --data " + data.string() + " --motor " + (data / "motor.toml").string() + " --set lambda_9=3 --out " + (t.path() / "o3").string(), "lambda_9"},
      {"generate --out " + (t.path() / "g1").string() + " --hidden warp_drive", "warp_drive"},
      {"generate --out " + data.string(), "exists"},
      {"generate --cycles 0 --out " + (t.path() / "g2").string(), "--cycles"},
      {"frobnicate", "frobnicate"},
  };
  for (const Case& c : cases) {
    const Result r = run(c.args, t.path());
    EXPECT_NE(r.code, 0) << c.args;
    EXPECT_EQ(lines(r.err), 1) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.must_name), std::string::npos) << c.args << "\n" << r.err;
  }
  for (const char* never : {"o1", "o2", "o3", "g1", "g2"}) EXPECT_FALSE(std::filesystem::exists(t.path() / never)) << never;
  // Nothing temporary left behind either.
  for (const auto& entry : std::filesystem::directory_iterator(t.path()))
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
}

}  // namespace
}  // namespace lptn::cli
