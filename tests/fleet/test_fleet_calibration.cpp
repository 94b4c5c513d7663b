// Fleets from the synthetic plant (lptn generate --fleet), calibrated whole: each motor's cooling
// factor against its truth, the weak motor named and no other, and healthy fleets over several
// seeds named clean. The truth's scale is the plant's convention, the fit's the fleet's median
// motor: factors compare as c / median(c) on both sides.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hostio/bad_input.hpp"
#include "lptn_testing/temp_dir.hpp"
#include "simulator/generate/generate.hpp"
#include "trainer/calibrate/calibration_result.hpp"
#include "trainer/lm/lm_result.hpp"
#include "trainer/fleet/fleet_calibration.hpp"
#include "trainer/fleet/fleet_file.hpp"
#include "trainer/fleet/outlier_test.hpp"

namespace lptn::fleet {
namespace {

struct FleetCase {
  testing::TempDir dir;
  std::vector<gen::FleetMotorSummary> truth;
  FleetDump fleet;
  MotorFile motor;
  calibrate::Split split;
  FleetFit fit;
};

// Six motors, two cycles of 50-70 minutes each: half a day of fleet data.
std::unique_ptr<FleetCase> calibrated_fleet(std::uint64_t seed, int weak) {
  auto c = std::make_unique<FleetCase>();
  gen::FleetOptions o;
  o.motors = 6;
  o.weak_motors = weak;
  o.motor.cycles = 2;
  o.motor.seed = seed;
  o.motor.min_duration_s = 3000;
  o.motor.max_duration_s = 4200;
  c->truth = gen::generate_fleet(o, c->dir.path());
  c->fleet = load_fleet(c->dir.path());
  c->motor = load_motor_file(c->dir.path() / "motor.toml");
  c->split = calibrate::split_cycles(c->fleet.dataset.data, {}, 1.0 / 3.0, seed);
  c->fit = fit_fleet(c->motor, c->fleet, c->split.train, FleetSettings{},
                     [](const std::string& line) { std::printf("  %s\n", line.c_str()); });
  return c;
}

// The factors' median as the fit normalizes: that of their logarithms (outlier_test.hpp's).
double median_factor(std::vector<double> factors) {
  for (double& f : factors) f = std::log(f);
  return std::exp(median(factors));
}

TEST(FleetCalibration, FindsEveryMotorsCoolingAndNamesTheWeakMotorAlone) {
  const auto c = calibrated_fleet(3, 1);
  ASSERT_EQ(c->fit.motors.size(), 6u);
  std::vector<double> true_factors;
  for (const auto& m : c->truth) true_factors.push_back(m.cooling_factor);
  const double true_median = median_factor(true_factors);
  int weak_named = 0, healthy_named = 0;
  for (std::size_t m = 0; m < 6; ++m) {
    const FleetMotorResult& r = c->fit.motors[m];
    const gen::FleetMotorSummary& t = c->truth[m];
    ASSERT_EQ(r.id, t.id);
    const double truth = t.cooling_factor / true_median;
    std::printf("%s: cooling %.4f +- %.4f, truth %.4f (%+.2f %%)%s; t = %+.2f; %s\n", r.id.c_str(), r.cooling_factor,
                r.cooling_factor_std, truth, 100 * (r.cooling_factor / truth - 1), t.weak ? " weak" : "", r.verdict.t,
                r.verdict.reason.c_str());
    EXPECT_NEAR(r.cooling_factor / truth, 1.0, 0.05) << r.id;
    // Its error bar is honest: the miss is within a few standard errors (or 1 %, the scatter of
    // the shared fit's own error).
    EXPECT_LT(std::abs(r.cooling_factor / truth - 1), std::max(4 * r.cooling_factor_std / r.cooling_factor, 0.01)) << r.id;
    if (t.weak) weak_named += r.verdict.outlier;
    else healthy_named += r.verdict.outlier;
  }
  EXPECT_EQ(weak_named, 1);
  EXPECT_EQ(healthy_named, 0);
  // The median motor cools as the shared parameters say, and the shared fit absorbs the scale.
  std::vector<double> fitted;
  for (const auto& r : c->fit.motors) fitted.push_back(r.cooling_factor);
  EXPECT_NEAR(median_factor(fitted), 1.0, 1e-12);
  std::printf("%d rounds, %.1f s\n", c->fit.rounds, c->fit.seconds);

  // fleet.json: written, read back, one motor exported as a calibration of its own.
  calibrate::CalibrationResult pooled = calibrate::new_calibration(c->motor, "motor.toml", c->fleet.dataset, c->split);
  lm::record_lm_fit(pooled, c->fit.shared, calibrate::FreeParameters::from_motor(c->motor), pooled.train_cycles, lm::to_json(lm::LmSettings{}));
  calibrate::score_calibration(pooled, c->motor, c->fleet.dataset, c->split);
  const auto path = c->dir.path() / "fleet.json";
  save_fleet(path, pooled, c->fit, FleetSettings{});
  const FleetFile file = load_fleet_file(path);
  ASSERT_EQ(file.motors.size(), 6u);
  for (std::size_t m = 0; m < 6; ++m) {
    EXPECT_EQ(file.motors[m].id, c->fit.motors[m].id);
    EXPECT_EQ(file.motors[m].outlier, c->fit.motors[m].verdict.outlier);
    const calibrate::CalibrationResult one = motor_calibration(file, file.motors[m].id);
    const ParamVector<double> values = one.values();
    for (int i = 0; i < kNumParams; ++i)
      EXPECT_DOUBLE_EQ(values[static_cast<std::size_t>(i)], c->fit.motors[m].parameters[static_cast<std::size_t>(i)]);
  }
  EXPECT_THROW(motor_calibration(file, "motor_99"), hostio::BadInput);
  EXPECT_EQ(file.rounds, c->fit.rounds);
  EXPECT_EQ(file.motors[2].cooling_factor, c->fit.motors[2].cooling_factor);  // bit for bit
  EXPECT_EQ(file.motors[2].t, c->fit.motors[2].verdict.t);

  // A hand-edited fleet.json: one line naming the file and the field.
  const std::string id = c->fit.motors[2].id;
  auto error_after = [&](const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json j = nlohmann::json::parse(testing::slurp(path));
    edit(j);
    const auto edited = c->dir.path() / "edited.json";
    std::ofstream(edited) << j.dump(2);
    try {
      load_fleet_file(edited);
    } catch (const calibrate::CalibrationFileError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string edited = (c->dir.path() / "edited.json").string();
  EXPECT_EQ(error_after([&](nlohmann::json& j) { j["motors"][id]["cooling_factor"] = "1.1"; }),
            edited + ": field 'motors." + id + ".cooling_factor': expected a number");
  EXPECT_EQ(error_after([&](nlohmann::json& j) { j["fleet"].erase("rounds"); }), edited + ": field 'fleet.rounds': missing");
  EXPECT_EQ(error_after([&](nlohmann::json& j) { j["motors"][id]["parameters"][0]["name"] = "lambda_9"; }),
            edited + ": field 'motors." + id + ".parameters[0].name': unknown parameter 'lambda_9'");
  EXPECT_EQ(error_after([&](nlohmann::json& j) { j["format_version"] = 7; }),
            edited + ": field 'format_version': version 7, this lptn reads 1");
}

TEST(FleetCalibration, NamesNoMotorOfHealthyFleetsOverSeeds) {
  int named = 0;
  for (std::uint64_t seed : {21u, 22u, 23u}) {
    const auto c = calibrated_fleet(seed, 0);
    for (const FleetMotorResult& r : c->fit.motors) {
      std::printf("seed %llu %s: cooling %.4f +- %.4f, t = %+.2f\n", static_cast<unsigned long long>(seed),
                  r.id.c_str(), r.cooling_factor, r.cooling_factor_std, r.verdict.t);
      named += r.verdict.outlier;
    }
  }
  EXPECT_EQ(named, 0);
}

}  // namespace
}  // namespace lptn::fleet
