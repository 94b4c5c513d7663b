// lptn check --fleet under mpirun: the motors shared over the ranks give the verdicts one process
// gives, word for word, and the same exit code.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "lptn_testing/run_lptn.hpp"
#include "lptn_testing/temp_dir.hpp"

namespace lptn::check {
namespace {

testing::Result under_mpirun(int ranks, const std::string& args, const std::filesystem::path& scratch) {
  // Open MPI refuses root unless told; CI runs as root. Ranks beyond the cores: --oversubscribe.
  setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  const std::string cmd = std::string(MPIEXEC) + " -np " + std::to_string(ranks) + " --oversubscribe " + LPTN_BINARY +
                          " " + args + " >" + (scratch / "stdout.txt").string() + " 2>" + (scratch / "stderr.txt").string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, testing::slurp(scratch / "stdout.txt"),
          testing::slurp(scratch / "stderr.txt")};
}

TEST(CheckMpi, SharedMotorsGiveOneProcesssVerdicts) {
  testing::TempDir t;
  const auto fleet = t.path() / "fleet", cal = t.path() / "cal.json";
  ASSERT_EQ(testing::run("generate --fleet --motors 4 --weak-motors 1 --cycles 2 --seed 21 --minutes-min 20 "
                         "--minutes-max 25 --out " + fleet.string(), t.path()).code, 0);
  std::string healthy;
  const auto truth = nlohmann::json::parse(std::ifstream(fleet / "truth.json"));
  for (const auto& [id, m] : truth["motors"].items())
    if (!m["weak"].get<bool>() && healthy.empty()) healthy = id;
  const testing::Result c = testing::run("calibrate --quiet --data " + (fleet / healthy).string() + " --motor " +
                                         (fleet / "motor.toml").string() + " --method lm --out " + cal.string(), t.path());
  ASSERT_TRUE(c.code == 0 || c.code == 3) << c.err;
  const std::string args = "check --quiet --json --fleet " + fleet.string() + " --calibration " + cal.string();
  const testing::Result alone = testing::run(args, t.path());
  ASSERT_NE(alone.code, 2) << alone.err;
  const auto expected = nlohmann::json::parse(alone.out);
  EXPECT_FALSE(expected["not_holding"].empty());  // the weak motor at least
  for (int ranks : {2, 3}) {
    const testing::Result shared = under_mpirun(ranks, args, t.path());
    EXPECT_EQ(shared.code, alone.code) << ranks << " ranks: " << shared.err;
    EXPECT_EQ(nlohmann::json::parse(shared.out), expected) << ranks << " ranks";
  }
  // One dump is not shared: refused before any work.
  const testing::Result data = under_mpirun(2, "check --data " + (fleet / healthy).string() + " --calibration " +
                                                   cal.string(), t.path());
  EXPECT_EQ(data.code, 2);
  EXPECT_NE(data.err.find("check --data under mpirun"), std::string::npos) << data.err;
}

}  // namespace
}  // namespace lptn::check
