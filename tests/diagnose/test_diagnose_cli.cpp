// lptn diagnose and lptn calibrate --effect as a user runs them.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "lptn_testing/run_lptn.hpp"
#include "lptn_testing/temp_dir.hpp"
#include "lptn_testing/sound_candidates.hpp"
#include "trainer/diagnose/diagnose.hpp"

namespace lptn::diagnose {
namespace {

using testing::Result;
using testing::run;

// Generates into DIR and calibrates the paper's model on all but the last two cycles.
std::string generate_and_calibrate(const testing::TempDir& t, const std::string& hidden) {
  const std::string data = (t.path() / "fleet").string(), cal = (t.path() / "calibration.json").string();
  const Result g = run("generate --out " + data + " --cycles 6 --seed 3 --minutes-min 25 --minutes-max 30" +
                           (hidden.empty() ? "" : " --hidden " + hidden),
                       t.path());
  EXPECT_EQ(g.code, 0) << g.err;
  const Result c = run("calibrate --data " + data + " --motor " + data + "/motor.toml --quiet --out " + cal +
                           " --test-cycles cycle_05_shunting,cycle_06_suburban",
                       t.path());
  // Written: the paper's model on data with hidden effects may end with warnings (a conductance on
  // its bound), never failed.
  EXPECT_TRUE(c.code == 0 || c.code == 3) << c.code << c.err;
  return "--data " + data + " --calibration " + cal;
}

// A sensor fault from generate to calibrate and check as a user types them; bad specs are one line
// naming the option and the field, and nothing is written.
TEST(DiagnoseCli, ASensorFaultIsGeneratedCalibratedAroundAndKept) {
  testing::TempDir t;
  const std::string data = (t.path() / "fleet").string(), cal = (t.path() / "cal.json").string();
  const Result bad_generate = run("generate --out " + data + " --cycles 4 --sensor-fault stator:offset:3:5", t.path());
  EXPECT_NE(bad_generate.code, 0);
  EXPECT_NE(bad_generate.err.find("--sensor-fault"), std::string::npos) << bad_generate.err;
  EXPECT_NE(bad_generate.err.find("from 1 to 4"), std::string::npos) << bad_generate.err;
  EXPECT_FALSE(std::filesystem::exists(data));
  const Result g = run("generate --out " + data + " --cycles 4 --seed 2 --minutes-min 5 --minutes-max 6 "
                       "--sensor-fault stator:offset:3:3", t.path());
  ASSERT_EQ(g.code, 0) << g.err;
  const auto truth = nlohmann::json::parse(std::ifstream(data + "/truth.json"));
  EXPECT_EQ(truth["sensor_faults"][0]["spec"], "stator:offset:+3.00:cycle_03_intercity");

  const std::string calibrate = "calibrate --data " + data + " --motor " + data + "/motor.toml --quiet --out " + cal;
  for (const char* spec : {"stator:offset:three:cycle_03_intercity", "stator:shift:3:cycle_03_intercity",
                           "stator:offset:3:cycle_07_nowhere", "stator:gain:1.03:cycle_03_intercity"}) {
    const Result r = run(calibrate + " --sensor-fault " + spec, t.path());
    EXPECT_NE(r.code, 0) << spec;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("--sensor-fault"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(cal)) << spec;
  }
  const Result c = run(calibrate + " --sensor-fault stator:offset:+3.0:cycle_03_intercity", t.path());
  ASSERT_TRUE(c.code == 0 || c.code == 3) << c.err;
  const auto j = nlohmann::json::parse(std::ifstream(cal));
  EXPECT_EQ(j["data"]["sensor_faults"], nlohmann::json::array({"stator:offset:+3.0:cycle_03_intercity"}));
  // Said, not only kept: on board the sensor still reads that way.
  bool warned = false;
  for (const auto& w : j["warnings"]) warned = warned || w["code"] == "sensor_fault";
  EXPECT_TRUE(warned) << j["warnings"].dump();
  EXPECT_EQ(c.code, 3) << "status warnings";
  {
    // A calibration whose fault cannot be read is named where it is wrong, before any work.
    nlohmann::json bad = j;
    bad["data"]["sensor_faults"] = {"stator:offset:3:cycle_03_intercity", "stator:sideways:3:cycle_03_intercity"};
    std::ofstream((t.path() / "bad.json").string()) << bad.dump(2);
    const Result r = run("check --data " + data + " --calibration " + (t.path() / "bad.json").string(), t.path());
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("sensor_faults"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("sideways"), std::string::npos) << r.err;
  }
  // The readings as the calibration saw them: corrected again, and said.
  const Result k = run("check --data " + data + " --calibration " + cal, t.path());
  EXPECT_NE(k.out.find("readings corrected for the sensor fault the calibration was made around: "
                       "stator:offset:+3.0:cycle_03_intercity"), std::string::npos) << k.out;
}

TEST(DiagnoseCli, CallsNothingSignificantWhereNothingIsHidden) {
  testing::TempDir t;
  const std::string args = generate_and_calibrate(t, "");
  const Result r = run("diagnose --json --quiet " + args, t.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_GT(j["rmse_k"].get<double>(), 0.0);
  diagnose::expect_sound_candidates(j, "clean, lptn diagnose --json");
  // Every effect of the library, and the dictionary's best-scoring terms (Settings::term_refits).
  const auto count = [&](const char* kind) {
    return std::count_if(j["candidates"].begin(), j["candidates"].end(), [&](const auto& c) { return c["kind"] == kind; });
  };
  EXPECT_EQ(count("library"), 5);
  EXPECT_EQ(count("term"), diagnose::Settings{}.term_refits);
  EXPECT_EQ(j["candidates"].size(), 5u + diagnose::Settings{}.term_refits);
  for (const auto& c : j["candidates"]) {
    for (const char* key : {"effect", "statistic", "predicted_rmse_k", "refit_rmse_k", "significant", "kind",
                            "recommended", "test_rmse_k_before", "test_rmse_k_after"})
      EXPECT_TRUE(c.contains(key)) << key;
    EXPECT_FALSE(c["significant"].get<bool>()) << c.dump();
    EXPECT_FALSE(c["recommended"].get<bool>()) << c.dump();
  }
  // The model the data came from, calibrated: adequate on both sensors (docs/diagnosis.md).
  EXPECT_TRUE(j["adequate"].get<bool>()) << j["sensors"].dump();
  for (const char* sensor : {"stator", "rotor"})
    for (const char* key : {"rmse_k", "noise_k", "adequate", "train_rmse_k", "test_rmse_k"})
      EXPECT_TRUE(j["sensors"][sensor].contains(key)) << sensor << "." << key;
  const Result text = run("diagnose --quiet " + args, t.path());
  EXPECT_NE(text.out.find("No effect of the library and no term of the dictionary improves the fit significantly"),
            std::string::npos) << text.out;
  EXPECT_NE(text.out.find("gives no reason to add one"), std::string::npos) << text.out;
}

TEST(DiagnoseCli, AutoFindsTwoHiddenEffectsAndWritesTheCalibration) {
  testing::TempDir t;
  const std::string out = (t.path() / "final.json").string();
  const Result r = run("diagnose --auto --json --quiet --out " + out + " " + generate_and_calibrate(t, "windage,sensor_lag"), t.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  std::printf("%s\n", r.out.substr(0, 400).c_str());
  EXPECT_EQ(j["added"].get<std::set<std::string>>(), (std::set<std::string>{"windage", "sensor_lag"}));
  EXPECT_EQ(j["rounds"].size(), 3u);
  for (const auto& round : j["rounds"]) diagnose::expect_sound_candidates(round, "windage and sensor_lag, --auto");
  for (const auto& c : j["candidates"]) EXPECT_FALSE(c["significant"].get<bool>()) << c.dump();
  const auto final_cal = nlohmann::json::parse(std::ifstream(out));
  EXPECT_EQ(final_cal["effects"].get<std::set<std::string>>(), (std::set<std::string>{"windage", "sensor_lag"}));
  EXPECT_LT(final_cal["metrics"]["test"]["rmse_stator_k"].get<double>(), 2 * 0.4);
  EXPECT_LT(final_cal["metrics"]["test"]["rmse_rotor_k"].get<double>(), 2 * 0.5);
}

TEST(DiagnoseCli, BadInputIsOneLineAndExitTwo) {
  testing::TempDir t;
  const Result e = run("calibrate --data " + t.path().string() + " --motor m.toml --out c.json --effect nosuch", t.path());
  EXPECT_EQ(e.code, 2);
  EXPECT_NE(e.err.find("--effect: unknown effect 'nosuch' (known: airgap, windage"), std::string::npos) << e.err;
  const Result d = run("diagnose --data " + t.path().string() + " --calibration nosuch.json", t.path());
  EXPECT_EQ(d.code, 2);
  EXPECT_EQ(std::count(d.err.begin(), d.err.end(), '\n'), 1) << d.err;
  const Result o = run("diagnose --data " + t.path().string() + " --calibration c.json --out x.json", t.path());
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.err.find("only with --auto"), std::string::npos) << o.err;
}

}  // namespace
}  // namespace lptn::diagnose
