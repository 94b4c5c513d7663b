#include <gtest/gtest.h>

#include "plant_fixtures.hpp"
#include "simulator/plant/motor_spec.hpp"
#include "simulator/plant/train_spec.hpp"

namespace lptn::plant {
namespace {

using test::example_motor;

TEST(MotorSpec, DerivedRatings) {
  const MotorSpec m = example_motor();
  EXPECT_DOUBLE_EQ(base_speed_rpm(m), 1950.0);
  EXPECT_NEAR(rated_torque_nm(m), 310e3 / (2.0 * std::numbers::pi * 1950.0 / 60.0), 1e-9);
  EXPECT_NEAR(max_speed_rpm(m), 2.1 * 1950.0, 1e-9);
  // Psi = V_phase / (2 pi f) = 1900 / sqrt(3) / (2 pi 65)
  EXPECT_NEAR(rated_flux_linkage_wb(m), 2.6859, 1e-3);
  EXPECT_NEAR(rotor_resistance_ohm(m, 120.0), 0.10 * (1.0 + 0.0039 * 100.0), 1e-12);
  EXPECT_NEAR(stator_resistance_ohm(m, -10.0), 0.14 * (1.0 - 0.00393 * 30.0), 1e-12);
}

TEST(MotorSpec, TorqueEnvelopeRegions) {
  const MotorSpec m = example_motor();
  const double t_max = 1.6 * rated_torque_nm(m);
  const double nb = base_speed_rpm(m);
  // Constant torque up to base speed.
  EXPECT_DOUBLE_EQ(torque_limit_nm(m, 0.0), t_max);
  EXPECT_DOUBLE_EQ(torque_limit_nm(m, 0.7 * nb), t_max);
  EXPECT_DOUBLE_EQ(torque_limit_nm(m, nb), t_max);
  // Constant power between base and 1.6 x base.
  EXPECT_NEAR(torque_limit_nm(m, 1.2 * nb) * 1.2, torque_limit_nm(m, 1.5 * nb) * 1.5, 1e-9);
  // Power falling as 1/n (torque as 1/n^2) beyond, continuous at the corner.
  EXPECT_NEAR(torque_limit_nm(m, 1.8 * nb) * 1.8 * 1.8, torque_limit_nm(m, 2.1 * nb) * 2.1 * 2.1, 1e-9);
  EXPECT_NEAR(torque_limit_nm(m, 1.6 * nb * (1 + 1e-12)), torque_limit_nm(m, 1.6 * nb), 1e-6);
  EXPECT_LT(torque_limit_nm(m, 2.1 * nb), rated_torque_nm(m));
  // Reverse running has the same envelope.
  EXPECT_DOUBLE_EQ(torque_limit_nm(m, -1.7 * nb), torque_limit_nm(m, 1.7 * nb));
}

TEST(TrainSpec, GearPutsTopMotorSpeedAt165Kmh) {
  const MotorSpec m = example_motor();
  const TrainSpec t = default_train_spec(m);
  EXPECT_NEAR(motor_rpm_from_speed(t, 165.0 / 3.6), max_speed_rpm(m), 1e-9);
  EXPECT_GT(t.gear_ratio, 3.0);
  EXPECT_LT(t.gear_ratio, 6.0);
  EXPECT_NEAR(speed_mps_from_motor_rpm(t, motor_rpm_from_speed(t, 23.4)), 23.4, 1e-12);
  EXPECT_NEAR(torque_from_force_nm(t, force_from_torque_n(t, 1234.5)), 1234.5, 1e-9);
  const double mass = effective_mass_kg(t);
  EXPECT_GE(mass, 25000.0);
  EXPECT_LE(mass, 30000.0);
}

TEST(TrainSpec, StartingAccelerationIsThatOfATrain) {
  // Full torque at standstill should give an EMU-like 0.6-1.0 m/s^2, not a sports car's.
  const MotorSpec m = example_motor();
  const TrainSpec t = default_train_spec(m);
  const double a = force_from_torque_n(t, torque_limit_nm(m, 0.0)) / effective_mass_kg(t);
  EXPECT_GT(a, 0.6);
  EXPECT_LT(a, 1.0);
  EXPECT_DOUBLE_EQ(running_resistance_n(t, 0.0), 0.0);
  EXPECT_GT(running_resistance_n(t, 44.0), running_resistance_n(t, 20.0));
}

}  // namespace
}  // namespace lptn::plant
