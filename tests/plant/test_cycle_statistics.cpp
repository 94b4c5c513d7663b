#include <gtest/gtest.h>

#include "plant_fixtures.hpp"
#include "simulator/plant/driving_cycle.hpp"

namespace lptn::plant {
namespace {

using test::CycleStats;
using test::example_motor;

struct Expected {
  CycleKind kind;
  double min_top_kmh, max_top_kmh;
  double min_stops_per_h, max_stops_per_h;
  double min_standstill, max_standstill;
};

// What a timetable of each kind looks like over an hour.
constexpr Expected kExpected[] = {
    {CycleKind::suburban, 75.0, 105.0, 12.0, 30.0, 0.10, 0.45},
    {CycleKind::regional, 110.0, 145.0, 5.0, 18.0, 0.05, 0.40},
    {CycleKind::intercity, 150.0, 164.9, 1.0, 8.0, 0.02, 0.35},
    {CycleKind::hilly, 105.0, 145.0, 5.0, 18.0, 0.05, 0.40},
    {CycleKind::shunting, 8.0, 29.9, 4.0, 40.0, 0.40, 0.95},
};

class CycleStatistics : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(CycleStatistics, EachKindLooksLikeItsService) {
  const MotorSpec m = example_motor();
  const TrainSpec train = default_train_spec(m);
  for (const Expected& e : kExpected) {
    const auto c = drive_cycle(e.kind, m, train, {}, 3600.0, 1.0, GetParam());
    const CycleStats s = test::cycle_stats(c, m, train);
    SCOPED_TRACE(std::string(to_string(e.kind)));
    EXPECT_GE(s.max_speed_kmh, e.min_top_kmh);
    EXPECT_LE(s.max_speed_kmh, e.max_top_kmh);
    EXPECT_GE(s.stops_per_hour, e.min_stops_per_h);
    EXPECT_LE(s.stops_per_hour, e.max_stops_per_h);
    EXPECT_GE(s.standstill_share, e.min_standstill);
    EXPECT_LE(s.standstill_share, e.max_standstill);
  }
}

TEST_P(CycleStatistics, HillyLinesHoldFullTorqueLongerThanRegional) {
  const MotorSpec m = example_motor();
  const TrainSpec train = default_train_spec(m);
  const auto hilly = test::cycle_stats(drive_cycle(CycleKind::hilly, m, train, {}, 7200.0, 1.0, GetParam()), m, train);
  const auto regional =
      test::cycle_stats(drive_cycle(CycleKind::regional, m, train, {}, 7200.0, 1.0, GetParam()), m, train);
  EXPECT_GT(hilly.longest_full_torque_s, 1.2 * regional.longest_full_torque_s);
  EXPECT_GT(regional.longest_full_torque_s, 20.0);  // a regional start is at full torque too
}

INSTANTIATE_TEST_SUITE_P(Seeds, CycleStatistics, ::testing::Values(1u, 2u, 3u, 4u, 5u));

TEST(CycleStatistics, ShuntingMovesBothWaysSlowly) {
  const MotorSpec m = example_motor();
  const TrainSpec train = default_train_spec(m);
  const auto c = drive_cycle(CycleKind::shunting, m, train, {}, 7200.0, 1.0, 12);
  int reversals = 0;
  double last_sign = 0.0;
  for (const DriveSample& x : c) {
    if (std::abs(x.speed_rpm) < 1.0) continue;
    const double sign = x.speed_rpm > 0.0 ? 1.0 : -1.0;
    if (last_sign != 0.0 && sign != last_sign) ++reversals;
    last_sign = sign;
    EXPECT_LT(3.6 * speed_mps_from_motor_rpm(train, std::abs(x.speed_rpm)), 30.0);
  }
  EXPECT_GE(reversals, 5);
}

}  // namespace
}  // namespace lptn::plant
