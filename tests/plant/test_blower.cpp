#include <gtest/gtest.h>

#include <cmath>

#include "plant_fixtures.hpp"
#include "simulator/plant/driving_cycle.hpp"

namespace lptn::plant {
namespace {

using test::example_motor;

constexpr std::size_t kRecent = 300;  // 5 min of 1 s samples: "the recent load"

struct Series {
  std::vector<double> airflow, power, recent_power;
};

Series series(CycleKind kind, BlowerPolicy policy, std::uint64_t seed, double duration_s = 7200.0) {
  const MotorSpec m = example_motor();
  const auto c = drive_cycle(kind, m, default_train_spec(m), policy, duration_s, 1.0, seed);
  Series s;
  for (const DriveSample& x : c) {
    s.airflow.push_back(x.airflow_m3s);
    s.power.push_back(std::abs(test::mech_power_w(x)));
  }
  s.recent_power = test::trailing_mean(s.power, kRecent);
  return s;
}

TEST(Blower, SteppedAirflowIsNotCorrelatedWithLoad) {
  for (const CycleKind kind : kAllCycleKinds) {
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
      const Series s = series(kind, {BlowerMode::stepped, 1.0, 1.0}, seed);
      EXPECT_LT(std::abs(test::correlation(s.airflow, s.power)), 0.3) << to_string(kind) << " " << seed;
    }
  }
}

TEST(Blower, SteppedAirflowIsNotCorrelatedWithRecentLoadOverAShift) {
  // Against a slow signal like the 5-min load, two hours hold only ~10 independent levels and a
  // chance correlation of +-0.3 is ordinary; over a 12 h shift (~60 levels) it is not.
  for (const CycleKind kind : kAllCycleKinds) {
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
      const Series s = series(kind, {BlowerMode::stepped, 1.0, 1.0}, seed, 12.0 * 3600.0);
      EXPECT_LT(std::abs(test::correlation(s.airflow, s.recent_power)), 0.3) << to_string(kind) << " " << seed;
    }
  }
}

TEST(Blower, LoadFollowingAirflowTracksTheRecentLoad) {
  for (const CycleKind kind : kAllCycleKinds) {
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
      const Series s = series(kind, {BlowerMode::load_following, 1.0, 1.0}, seed);
      EXPECT_GT(test::correlation(s.airflow, s.recent_power), 0.45) << to_string(kind) << " " << seed;
      EXPECT_GT(test::correlation(s.airflow, s.power), 0.05) << to_string(kind) << " " << seed;
    }
  }
}

TEST(Blower, LevelsStayInTheirBands) {
  for (const CycleKind kind : {CycleKind::suburban, CycleKind::hilly}) {
    const Series lf = series(kind, {BlowerMode::load_following, 1.0, 2.0}, 8);
    const auto [lf_min, lf_max] = std::minmax_element(lf.airflow.begin(), lf.airflow.end());
    EXPECT_GE(*lf_min, 0.35 * 2.0);
    EXPECT_LE(*lf_max, 1.0 * 2.0);
    EXPECT_GT(*lf_max - *lf_min, 0.5);  // it really follows the load
    const Series st = series(kind, {BlowerMode::stepped, 1.0, 2.0}, 8);
    const auto [st_min, st_max] = std::minmax_element(st.airflow.begin(), st.airflow.end());
    EXPECT_GE(*st_min, 0.3 * 2.0);
    EXPECT_LE(*st_max, 1.0 * 2.0);
  }
}

TEST(Blower, FixedLevelIsConstantUpToFanNoise) {
  const Series s = series(CycleKind::regional, {BlowerMode::fixed, 0.6, 1.5}, 3);
  double sum = 0.0, sq = 0.0;
  for (const double a : s.airflow) {
    sum += a;
    sq += a * a;
  }
  const auto n = static_cast<double>(s.airflow.size());
  const double mean = sum / n;
  EXPECT_NEAR(mean, 0.9, 0.01);
  EXPECT_GT(std::sqrt(sq / n - mean * mean), 0.0);  // a real fan is never perfectly steady
  EXPECT_LT(std::sqrt(sq / n - mean * mean), 0.02);
}

TEST(Blower, SteppedLevelChangesEveryEightToFifteenMinutes) {
  // Count jumps (the fan settles within ~30 s; noise is far below 0.04 of nominal).
  const Series s = series(CycleKind::suburban, {BlowerMode::stepped, 1.0, 1.0}, 21, 4.0 * 3600.0);
  int jumps = 0;
  std::size_t last_jump = 0;
  for (std::size_t i = 30; i < s.airflow.size(); ++i) {
    if (std::abs(s.airflow[i] - s.airflow[i - 30]) > 0.04 && (jumps == 0 || i - last_jump > 120)) {
      ++jumps;
      last_jump = i;
    }
  }
  // 4 h / 8..15 min = 16..30 changes; a few may be too small to see.
  EXPECT_GE(jumps, 12);
  EXPECT_LE(jumps, 30);
}

TEST(Blower, LoadFollowingRunsOnAfterTheTrainStops) {
  const MotorSpec m = example_motor();
  const auto c = drive_cycle(CycleKind::intercity, m, default_train_spec(m), {BlowerMode::load_following, 1.0, 1.0},
                             7200.0, 1.0, 5);
  int checked = 0;
  for (std::size_t i = 600; i + 60 < c.size(); ++i) {
    const bool arrives = std::abs(c[i - 1].speed_rpm) > 0.5 && std::abs(c[i].speed_rpm) <= 0.5;
    if (!arrives || std::abs(c[i + 60].speed_rpm) > 0.5) continue;
    // A minute after stopping the fan is still well above its minimum, and coming down.
    EXPECT_GT(c[i + 60].airflow_m3s, 0.5) << c[i].t_s;
    EXPECT_LT(c[i + 60].airflow_m3s, c[i].airflow_m3s) << c[i].t_s;
    ++checked;
  }
  EXPECT_GE(checked, 3);
}

}  // namespace
}  // namespace lptn::plant
