#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "plant_fixtures.hpp"
#include "simulator/plant/ambient.hpp"
#include "simulator/plant/driving_cycle.hpp"

namespace lptn::plant {
namespace {

using test::example_motor;

constexpr double kHour = 3600.0;

std::vector<DriveSample> cycle(CycleKind kind, std::uint64_t seed, double duration_s = kHour, double dt_s = 1.0,
                               BlowerPolicy blower = {}) {
  const MotorSpec m = example_motor();
  return drive_cycle(kind, m, default_train_spec(m), blower, duration_s, dt_s, seed);
}

bool same_drive(const std::vector<DriveSample>& a, const std::vector<DriveSample>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].t_s != b[i].t_s || a[i].speed_rpm != b[i].speed_rpm || a[i].torque_nm != b[i].torque_nm) return false;
  }
  return true;
}

TEST(DriveCycle, SameSeedGivesTheIdenticalCycle) {
  for (const CycleKind kind : kAllCycleKinds) {
    const auto a = cycle(kind, 42);
    const auto b = cycle(kind, 42);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a[i].speed_rpm, b[i].speed_rpm) << to_string(kind) << " sample " << i;
      ASSERT_EQ(a[i].torque_nm, b[i].torque_nm);
      ASSERT_EQ(a[i].airflow_m3s, b[i].airflow_m3s);
      ASSERT_EQ(a[i].ambient_c, b[i].ambient_c);
    }
  }
}

TEST(DriveCycle, DifferentSeedGivesADifferentCycle) {
  for (const CycleKind kind : kAllCycleKinds) {
    const auto a = cycle(kind, 42);
    const auto b = cycle(kind, 43);
    EXPECT_FALSE(same_drive(a, b)) << to_string(kind);
    std::size_t differing_ambient = 0;
    for (std::size_t i = 0; i < a.size(); ++i) differing_ambient += a[i].ambient_c != b[i].ambient_c;
    EXPECT_GT(differing_ambient, a.size() / 2);
  }
}

TEST(DriveCycle, BlowerPolicyDoesNotChangeTheDrive) {
  // Separate random streams: a calibrator can compare blower policies on the very same drive.
  const auto a = cycle(CycleKind::regional, 7, kHour, 1.0, {BlowerMode::load_following, 1.0, 1.0});
  const auto b = cycle(CycleKind::regional, 7, kHour, 1.0, {BlowerMode::stepped, 1.0, 1.0});
  EXPECT_TRUE(same_drive(a, b));
  std::size_t differing_air = 0;
  for (std::size_t i = 0; i < a.size(); ++i) differing_air += a[i].airflow_m3s != b[i].airflow_m3s;
  EXPECT_GT(differing_air, a.size() / 2);
}

TEST(DriveCycle, TorqueNeverExceedsTheMotorEnvelope) {
  const MotorSpec m = example_motor();
  for (const CycleKind kind : kAllCycleKinds) {
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
      const auto c = cycle(kind, seed, 2.0 * kHour, 0.5);
      double worst = 0.0;
      for (const DriveSample& x : c) worst = std::max(worst, std::abs(x.torque_nm) / torque_limit_nm(m, x.speed_rpm));
      EXPECT_LE(worst, 1.0 + 1e-12) << to_string(kind) << " seed " << seed;
      // ... and the generator does use the envelope (shunting drives gently).
      if (kind != CycleKind::shunting) {
        EXPECT_GT(worst, 0.999) << to_string(kind);
      }
    }
  }
}

TEST(DriveCycle, SampleGridAndArguments) {
  const auto c = cycle(CycleKind::suburban, 5, 3600.0, 0.5);
  ASSERT_EQ(c.size(), 7201u);
  EXPECT_EQ(c.front().t_s, 0.0);
  EXPECT_DOUBLE_EQ(c[3].t_s, 1.5);
  EXPECT_DOUBLE_EQ(c.back().t_s, 3600.0);
  EXPECT_EQ(cycle(CycleKind::regional, 5, 3600.0, 2.0).size(), 1801u);
  EXPECT_EQ(cycle(CycleKind::regional, 5, 3601.0, 2.0).size(), 1801u);
  const MotorSpec m = example_motor();
  EXPECT_THROW(drive_cycle(CycleKind::regional, m, default_train_spec(m), {}, 3600.0, 0.0, 1), std::invalid_argument);
  EXPECT_THROW(drive_cycle(CycleKind::regional, m, default_train_spec(m), {}, -1.0, 1.0, 1), std::invalid_argument);
}

TEST(DriveCycle, OutputStepDoesNotChangeTheDrive) {
  // The train runs on the same internal 0.25 s grid whatever the output step: samples at
  // common times agree exactly.
  const auto fine = cycle(CycleKind::intercity, 11, kHour, 0.5);
  const auto coarse = cycle(CycleKind::intercity, 11, kHour, 2.0);
  for (std::size_t i = 0; i < coarse.size(); ++i) {
    ASSERT_EQ(coarse[i].speed_rpm, fine[4 * i].speed_rpm) << i;
    ASSERT_EQ(coarse[i].torque_nm, fine[4 * i].torque_nm) << i;
  }
}

TEST(DriveCycle, OnlyShuntingRunsInReverse) {
  for (const CycleKind kind : kAllCycleKinds) {
    const auto c = cycle(kind, 9, 2.0 * kHour);
    bool reverse = false;
    for (const DriveSample& x : c) reverse = reverse || x.speed_rpm < -1.0;
    EXPECT_EQ(reverse, kind == CycleKind::shunting) << to_string(kind);
  }
}

TEST(DriveCycle, ElectricBrakeFadesOutBelowFiveKmh) {
  const MotorSpec m = example_motor();
  const TrainSpec train = default_train_spec(m);
  for (const CycleKind kind : kAllCycleKinds) {
    const auto c = cycle(kind, 4, kHour, 0.25);
    bool braked_electrically = false;
    for (const DriveSample& x : c) {
      const double kmh = 3.6 * speed_mps_from_motor_rpm(train, std::abs(x.speed_rpm));
      const bool braking = x.torque_nm * x.speed_rpm < 0.0;
      if (kmh < train.electric_brake_min_kmh) {
        EXPECT_FALSE(braking) << to_string(kind) << " t=" << x.t_s;
      }
      braked_electrically = braked_electrically || braking;
    }
    EXPECT_TRUE(braked_electrically) << to_string(kind);
  }
}

TEST(DriveCycle, AmbientStaysInRangeAndDrifts) {
  const double lo = kAmbientBaseMin_c - kAmbientDriftMax_k - kAmbientWanderMax_k - kTunnelDepthMax_k;
  const double hi = kAmbientBaseMax_c + kAmbientDriftMax_k + kAmbientWanderMax_k;
  double coldest = 1e9, warmest = -1e9;
  for (std::uint64_t seed = 0; seed < 40; ++seed) {
    const auto c = cycle(CycleKind::regional, seed, kHour, 5.0);
    double mn = 1e9, mx = -1e9;
    for (const DriveSample& x : c) {
      mn = std::min(mn, x.ambient_c);
      mx = std::max(mx, x.ambient_c);
    }
    EXPECT_GE(mn, lo) << seed;
    EXPECT_LE(mx, hi) << seed;
    EXPECT_GT(mx - mn, 0.2) << seed;  // it does move: drift, wander, tunnels
    EXPECT_LT(mx - mn, 2.0 * kAmbientDriftMax_k + kTunnelDepthMax_k + 1.0) << seed;
    coldest = std::min(coldest, c.front().ambient_c);
    warmest = std::max(warmest, c.front().ambient_c);
  }
  // Forty seeds spread over the -10..35 C base range.
  EXPECT_LT(coldest, 0.0);
  EXPECT_GT(warmest, 25.0);
}

// Largest drop of the ambient within `window` samples: a tunnel shows as a few K in a minute.
double largest_quick_drop(const std::vector<DriveSample>& c, std::size_t window) {
  double drop = 0.0;
  for (std::size_t i = window; i < c.size(); ++i) drop = std::max(drop, c[i - window].ambient_c - c[i].ambient_c);
  return drop;
}

TEST(DriveCycle, TunnelsOnTheLineButNotInTheDepot) {
  EXPECT_GT(largest_quick_drop(cycle(CycleKind::intercity, 3, 2.0 * kHour), 90), 1.5);
  EXPECT_LT(largest_quick_drop(cycle(CycleKind::shunting, 3, 2.0 * kHour), 90), 0.5);
}

}  // namespace
}  // namespace lptn::plant
