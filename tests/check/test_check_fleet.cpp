// lptn check --fleet: a fleet calibrated when every motor was healthy, checked a month later when
// one motor's filter has clogged (30 % weaker cooling): that motor, and no other, is named.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "lptn_testing/run_lptn.hpp"
#include "lptn_testing/temp_dir.hpp"

namespace lptn::check {
namespace {

using testing::Result;
using testing::run;

std::string generate_fleet(const std::filesystem::path& dir, int seed, int weak) {
  return "generate --fleet --motors 6 --weak-motors " + std::to_string(weak) + " --cycles 2 --seed " +
         std::to_string(seed) + " --minutes-min 30 --minutes-max 40 --force --out " + dir.string();
}

TEST(CheckFleet, NamesTheMotorWhoseCoolingWeakenedSinceCalibration) {
  testing::TempDir t;
  const auto then = t.path() / "then", now = t.path() / "now", fleet = t.path() / "fleet.json";
  ASSERT_EQ(run(generate_fleet(then, 11, 0), t.path()).code, 0);
  const Result c = run("calibrate --quiet --fleet " + then.string() + " --motor " + (then / "motor.toml").string() +
                           " --method lm --out " + fleet.string(), t.path());
  ASSERT_TRUE(c.code == 0 || c.code == 3) << c.err;  // written: ok, or with warnings
  ASSERT_EQ(run(generate_fleet(now, 12, 1), t.path()).code, 0);
  std::string weak;
  const auto truth = nlohmann::json::parse(std::ifstream(now / "truth.json"));
  for (const auto& [id, m] : truth["motors"].items())
    if (m["weak"].get<bool>()) weak = id;

  const Result r = run("check --quiet --json --fleet " + now.string() + " --calibration " + fleet.string(), t.path());
  ASSERT_EQ(r.code, 1) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_FALSE(j["holds"].get<bool>());
  EXPECT_EQ(j["not_holding"], nlohmann::json::array({weak}));
  ASSERT_EQ(j["motors"].size(), 6u);
  for (const auto& m : j["motors"]) {
    EXPECT_EQ(m["holds"].get<bool>(), m["motor_id"] != weak) << m["motor_id"] << ": " << m["reasons"].dump();
    EXPECT_NE(m["against"].get<std::string>().find("its own cooling factor"), std::string::npos);
  }
  const Result text = run("check --quiet --fleet " + now.string() + " --calibration " + fleet.string(), t.path());
  EXPECT_NE(text.out.find("1 of 6 motors' calibration no longer holds: " + weak), std::string::npos) << text.out;

  // The fleet's own dump: every motor holds against its own factor, and the fleet file is refused
  // where one motor's data is given.
  const Result own = run("check --quiet --fleet " + then.string() + " --calibration " + fleet.string(), t.path());
  EXPECT_EQ(own.code, 0) << own.out;
  const Result kind = run("check --data " + (then / "motor_01").string() + " --calibration " + fleet.string(), t.path());
  EXPECT_EQ(kind.code, 2);
  EXPECT_NE(kind.err.find("a fleet calibration (lptn calibrate --fleet): use --fleet"), std::string::npos) << kind.err;
}

}  // namespace
}  // namespace lptn::check
