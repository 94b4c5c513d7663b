// Cooling health on board, on a fleet from the synthetic plant, the way an operator gets there:
// lptn generate --fleet, lptn calibrate --fleet, then each motor's log through lptn convert and
// lptn replay --fleet (the firmware's estimator with the type's pooled calibration, what every
// motor of the type is flashed with). Each motor's on-board cooling factor after an hour of driving is held
// against its truth (as a ratio to the fleet's median motor, the calibration's own scale), and the
// alarm must be raised on the weak motor's log and on no other.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lptn_testing/run_lptn.hpp"
#include "lptn_testing/temp_dir.hpp"
#include "lptn_testing/csv_columns.hpp"
#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/fleet/outlier_test.hpp"

namespace lptn::fleet {
namespace {

namespace fs = std::filesystem;
using lptn::testing::run;

// The factors' median as the fleet fit normalizes: that of their logarithms.
double median_factor(std::vector<double> factors) {
  for (double& f : factors) f = std::log(f);
  return std::exp(fleet::median(factors));
}

TEST(OnboardCooling, EachMotorsFactorWithin5PercentAfterAnHourAndTheAlarmOnTheWeakMotorAlone) {
  testing::TempDir dir;
  const fs::path d = dir.path(), fleet = d / "fleet";
  auto ok = [&](const std::string& args) {
    const auto r = run(args, d);
    ASSERT_EQ(r.code, 0) << args << "\n" << r.err;
  };
  // Six motors, one 30 % weaker, each a drive of 65-75 minutes.
  ok("generate --fleet --motors 6 --weak-motors 1 --cycles 1 --minutes-min 65 --minutes-max 75 --seed 7 --out " +
     fleet.string());
  ok("calibrate --fleet " + fleet.string() + " --motor " + (fleet / "motor.toml").string() +
     " --method lm --quiet --out " + (d / "fleet.json").string());
  const nlohmann::json truth = calibrate::read_lptn_json(fleet / "truth.json").at("motors");
  std::vector<double> factors;
  for (const auto& [id, m] : truth.items()) factors.push_back(m.at("cooling_factor").get<double>());
  const double fleet_median = median_factor(factors);

  int weak_alarmed = 0, healthy_alarmed = 0, weak = 0;
  for (const auto& [id, m] : truth.items()) {
    fs::path cycle;
    for (const auto& e : fs::directory_iterator(fleet / id))
      if (e.path().extension() == ".csv") cycle = e.path();
    const fs::path log = d / (id + ".log"), est = d / (id + ".csv");
    ok("convert --in " + cycle.string() + " --out " + log.string());
    ok("replay --quiet --log " + log.string() + " --fleet " + (d / "fleet.json").string() + " --out " + est.string());
    const auto csv = lptn::testing::read_csv_columns(est);
    const auto& t = csv.at("time_s");
    const auto& factor = csv.at("cooling_factor");
    const auto& spread = csv.at("cooling_factor_std");
    const auto& alarm = csv.at("cooling_alarm");
    const auto& state = csv.at("cooling_state");
    ASSERT_GT(t.back(), 3600.0) << id;
    const double want = m.at("cooling_factor").get<double>() / fleet_median;
    const bool is_weak = m.at("weak").get<bool>();
    // After an hour, and when it came within 5 % to stay.
    std::size_t hour = 0;
    while (t[hour] < 3600.0) ++hour;
    std::size_t settled = factor.size();
    while (settled > 0 && std::abs(factor[settled - 1] / want - 1) <= 0.05) --settled;
    const bool any_alarm = std::any_of(alarm.begin(), alarm.end(), [](double a) { return a == 1; });
    std::size_t first_alarm = 0;
    while (first_alarm < alarm.size() && alarm[first_alarm] != 1) ++first_alarm;
    std::printf("%s%s: after an hour %.4f +- %.4f, truth %.4f (%+.2f %%); within 5 %% from %.0f min on; alarm %s\n",
                id.c_str(), is_weak ? " (weak)" : "", factor[hour], spread[hour], want, 100 * (factor[hour] / want - 1),
                settled < t.size() ? t[settled] / 60 : -1.0,
                any_alarm ? ("from " + std::to_string(int(t[first_alarm] / 60)) + " min").c_str() : "never");
    EXPECT_NEAR(factor[hour] / want, 1.0, 0.05) << id;
    EXPECT_LE(t[std::min(settled, t.size() - 1)], 3600.0) << id << ": not within 5 % to stay by the hour";
    EXPECT_TRUE(std::all_of(state.begin(), state.end(), [](double s) { return s == 0; })) << id << ": tracking throughout";
    if (is_weak) {
      ++weak;
      weak_alarmed += alarm[hour] == 1 && alarm.back() == 1;
    } else {
      healthy_alarmed += any_alarm;
    }
  }
  EXPECT_EQ(weak, 1);
  EXPECT_EQ(weak_alarmed, 1) << "the weak motor's alarm up at the hour and at the end";
  EXPECT_EQ(healthy_alarmed, 0) << "an alarm on a healthy motor's log";
}

}  // namespace
}  // namespace lptn::fleet
