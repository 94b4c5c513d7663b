// lptn calibrate as a user runs it: calibration.json with its documented keys, train and test
// metrics, and one-line errors that leave nothing behind.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "lptn_testing/run_lptn.hpp"
#include "lptn_testing/temp_dir.hpp"

namespace lptn::cli {
namespace {

using testing::Result;
using testing::run;

class CalibrateCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir;
    const Result g = run("generate --out " + data().string() + " --cycles 3 --seed 4 --minutes-min 20 --minutes-max 25", dir_->path());
    ASSERT_EQ(g.code, 0) << g.err;
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::filesystem::path data() { return dir_->path() / "fleet"; }
  static std::string base() { return "calibrate --data " + data().string() + " --motor " + (data() / "motor.toml").string(); }
  static testing::TempDir* dir_;
};
testing::TempDir* CalibrateCli::dir_ = nullptr;

TEST_F(CalibrateCli, LmWritesTheDocumentedKeys) {
  testing::TempDir t;
  const auto out = t.path() / "calibration.json";
  const Result r = run(base() + " --method lm --test-cycles cycle_02_regional --out " + out.string(), t.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(std::ifstream(out));
  EXPECT_EQ(j["method"]["name"], "lm");
  EXPECT_EQ(j["data"]["split"]["test"], nlohmann::json::array({"cycle_02_regional"}));
  EXPECT_EQ(j["data"]["files"].size(), 3u);
  EXPECT_EQ(j["data"]["sha256"].get<std::string>().size(), 64u);
  for (const char* side : {"train", "test"})
    for (const char* key : {"rmse_stator_k", "mean_abs_stator_k", "max_abs_stator_k", "bias_stator_k", "rmse_rotor_k"}) {
      ASSERT_TRUE(j["metrics"][side].contains(key)) << side << "." << key;
      EXPECT_GE(j["metrics"][side][key].get<double>(), side == std::string("train") && key == std::string("bias_stator_k") ? -10.0 : 0.0);
    }
  // The fit brought the test cycle to the sensors' noise (0.4 K stator, 0.5 K rotor).
  EXPECT_LT(j["metrics"]["test"]["rmse_stator_k"].get<double>(), 0.6);
  EXPECT_LT(j["metrics"]["test"]["rmse_rotor_k"].get<double>(), 0.75);
  EXPECT_EQ(j["metrics"]["test"]["cycles"].size(), 1u);
  bool std_errors = false;
  for (const auto& p : j["parameters"])
    if (p["calibrated"].get<bool>()) std_errors = !p["std_error"].is_null();
  EXPECT_TRUE(std_errors);
  // The result feeds export.
  const Result e = run("export --calibration " + out.string() + " --out " + (t.path() / "h.hpp").string(), t.path());
  EXPECT_EQ(e.code, 0) << e.err;
}

// The benchmark's baselines run in lptn itself (no libtorch) and write an ordinary calibration.
TEST_F(CalibrateCli, TheSearchBaselinesWriteACalibrationWithTheirBudget) {
  testing::TempDir t;
  for (const char* method : {"random-search", "cma-es"}) {
    const auto out = t.path() / (std::string(method) + ".json");
    const Result r = run(base() + " --method " + method + " --budget-steps 3000000 --quiet --out " + out.string(), t.path());
    // A search this short stops far from LM's fit: random search 12x its sensors' noise off, which
    // the calibration says (exit 3); CMA-ES gets near.
    ASSERT_TRUE(r.code == 0 || r.code == 3) << r.err;
    const auto j = nlohmann::json::parse(std::ifstream(out));
    bool inadequate = false;
    for (const auto& w : j["warnings"]) inadequate = inadequate || w["code"] == "not_adequate";
    EXPECT_EQ(r.code == 3, !j["warnings"].empty()) << method;
    if (method == std::string("random-search")) {
      EXPECT_TRUE(inadequate) << r.err;
    }
    EXPECT_EQ(j["method"]["name"], method);
    EXPECT_GE(j["method"]["details"]["simulated_steps"].get<double>(), 3e6) << method;
    EXPECT_EQ(j["method"]["settings"]["budget_steps"], 3000000) << method;
    // The guess is 18 K off; even this budget gets far below it.
    EXPECT_LT(j["metrics"]["test"]["rmse_stator_k"].get<double>(), 5.0) << method;
  }
}

TEST_F(CalibrateCli, BadInputIsOneLineAndLeavesNothing) {
  testing::TempDir t;
  const auto out = t.path() / "calibration.json";
  const Result unknown = run(base() + " --method lm --test-cycles no_such_cycle --out " + out.string(), t.path());
  EXPECT_EQ(unknown.code, 2);
  EXPECT_NE(unknown.err.find("no cycle named 'no_such_cycle'"), std::string::npos) << unknown.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  const Result method = run(base() + " --method sgd --out " + out.string(), t.path());
  EXPECT_EQ(method.code, 2);
#if LPTN_WITH_TD3
  std::ofstream(t.path() / "bad.toml") << "[agent]\nhidden = -3\n";
  const Result config = run(base() + " --method td3 --config " + (t.path() / "bad.toml").string() + " --out " + out.string(), t.path());
  EXPECT_EQ(config.code, 2);
  EXPECT_NE(config.err.find("bad.toml:2: key 'agent.hidden'"), std::string::npos) << config.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  // A warm start from a calibration that is no td3 calibration with an agent (LM's, a whole one),
  // and from JSON that is no calibration at all.
  const Result lm = run(base() + " --method lm --quiet --out " + (t.path() / "lm.json").string(), t.path());
  ASSERT_TRUE(lm.code == 0 || lm.code == 3) << lm.err;
  const Result warm = run(base() + " --method td3 --warm-start " + (t.path() / "lm.json").string() + " --out " + out.string(), t.path());
  EXPECT_EQ(warm.code, 2);
  EXPECT_NE(warm.err.find("lm.json: method.details.agent_file"), std::string::npos) << warm.err;
  std::ofstream(t.path() / "other.json") << R"({"method": {"name": "td3", "details": {"agent_file": "a.pt"}}, "parameters": []})";
  const Result other = run(base() + " --method td3 --warm-start " + (t.path() / "other.json").string() + " --out " + out.string(), t.path());
  EXPECT_EQ(other.code, 2);
  EXPECT_NE(other.err.find("other.json: not a calibration file"), std::string::npos) << other.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(t.path() / "calibration.json.agent"));
#endif
  const Result warm_lm = run(base() + " --method cma-es --warm-start x.json --out " + out.string(), t.path());
  EXPECT_EQ(warm_lm.code, 2);
  EXPECT_NE(warm_lm.err.find("--warm-start: only with --method td3"), std::string::npos) << warm_lm.err;
  std::ofstream(out) << "keep me";
  const Result exists = run(base() + " --method lm --out " + out.string(), t.path());
  EXPECT_EQ(exists.code, 2);
  EXPECT_NE(exists.err.find("--force"), std::string::npos);
}

#if !LPTN_WITH_TD3
// Built without libtorch (LPTN_WITH_TD3=OFF): TD3 is bad input, one line, nothing written.
TEST_F(CalibrateCli, Td3WithoutLibtorchIsBadInput) {
  testing::TempDir t;
  const auto out = t.path() / "calibration.json";
  for (const char* method : {"td3", "td3-paper", "td3-episode"}) {
    const Result r = run(base() + " --method " + method + " --out " + out.string(), t.path());
    EXPECT_EQ(r.code, 2) << method;
    EXPECT_NE(r.err.find("built without libtorch"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
}
#endif

}  // namespace
}  // namespace lptn::cli
