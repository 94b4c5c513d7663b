#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "plant_fixtures.hpp"
#include "simulator/plant/operating_point.hpp"

namespace lptn::plant {
namespace {

using test::example_motor;

double mech_frequency_hz(const MotorSpec& m, double speed_rpm) { return m.pole_pairs * speed_rpm / 60.0; }

TEST(OperatingPoint, RotorCopperLossEqualsSlipPower) {
  const MotorSpec m = example_motor();
  const double tr = rated_torque_nm(m);
  int checked = 0;
  for (const double n : {-4000.0, -1950.0, -300.0, 0.0, 150.0, 1000.0, 1950.0, 2600.0, 3500.0, 4095.0}) {
    for (const double t_frac : {-1.6, -1.0, -0.3, -0.05, 0.05, 0.4, 1.0, 1.6}) {
      for (const double rotor_c : {-20.0, 20.0, 90.0, 180.0}) {
        const double t = std::clamp(t_frac * tr, -torque_limit_nm(m, n), torque_limit_nm(m, n));
        const OperatingPoint op = operating_point(m, n, t, rotor_c, 60.0);
        ASSERT_TRUE(op.pulses_on);
        // Slip power: torque times the slip angular frequency, mechanical side (divide by p).
        const double slip_power = t * 2.0 * std::numbers::pi * (op.frequency_hz - mech_frequency_hz(m, n)) / m.pole_pairs;
        EXPECT_GT(op.rotor_copper_w, 0.0);
        EXPECT_NEAR(op.rotor_copper_w, slip_power, 1e-9 * std::abs(slip_power)) << n << " rpm " << t << " Nm";
        EXPECT_NEAR(op.slip_hz, op.frequency_hz - mech_frequency_hz(m, n), 1e-12);
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 320);
}

TEST(OperatingPoint, SlipGrowsWithRotorTemperature) {
  const MotorSpec m = example_motor();
  const double t = 0.8 * rated_torque_nm(m);
  for (const double n : {500.0, 1500.0, 3000.0}) {
    double previous = 0.0;
    for (const double rotor_c : {0.0, 40.0, 80.0, 120.0, 160.0}) {
      const OperatingPoint op = operating_point(m, n, t, rotor_c, 80.0);
      EXPECT_GT(op.slip_hz, previous) << n << " rpm, " << rotor_c << " C";
      previous = op.slip_hz;
    }
  }
  // At rated flux the slip is proportional to R2(T): slip(120 C) / slip(20 C) = 1 + alpha * 100.
  const double cold = operating_point(m, 1000.0, t, 20.0, 20.0).slip_hz;
  const double hot = operating_point(m, 1000.0, t, 120.0, 20.0).slip_hz;
  EXPECT_NEAR(hot / cold, 1.0 + 0.0039 * 100.0, 1e-12);
}

TEST(OperatingPoint, RatedTorqueAtRatedSpeed) {
  const MotorSpec m = example_motor();
  const OperatingPoint op = operating_point(m, base_speed_rpm(m), rated_torque_nm(m), 110.0, 100.0);
  EXPECT_TRUE(op.pulses_on);
  EXPECT_NEAR(op.current_a, m.rated_current_a, 0.15 * m.rated_current_a);
  EXPECT_NEAR(op.voltage_v, m.rated_voltage_v, 0.05 * m.rated_voltage_v);
  EXPECT_NEAR(op.frequency_hz, m.rated_frequency_hz, 1.5);
  EXPECT_GT(op.slip_hz, 0.2);  // a 310 kW machine slips by ~1 %
  EXPECT_LT(op.slip_hz, 1.5);
}

TEST(OperatingPoint, FluxAndMagnetizingCurrentRatedBelowBaseSpeed) {
  const MotorSpec m = example_motor();
  const OperatingPoint op = operating_point(m, 900.0, rated_torque_nm(m), 80.0, 80.0);
  EXPECT_DOUBLE_EQ(op.flux_ratio, 1.0);
  EXPECT_DOUBLE_EQ(op.magnetizing_current_a, m.magnetizing_current_a);
  EXPECT_NEAR(op.current_a, std::hypot(op.magnetizing_current_a, op.rotor_current_a), 1e-9);
  // V roughly proportional to f below base: about half rated at half frequency.
  EXPECT_NEAR(op.voltage_v / m.rated_voltage_v, op.frequency_hz / m.rated_frequency_hz, 0.05);
}

TEST(OperatingPoint, FieldWeakeningAboveBaseSpeed) {
  const MotorSpec m = example_motor();
  const double n = 1.5 * base_speed_rpm(m);
  const double t = torque_limit_nm(m, n);
  const OperatingPoint op = operating_point(m, n, t, 100.0, 100.0);
  EXPECT_NEAR(op.flux_ratio, m.rated_frequency_hz / op.frequency_hz, 1e-12);
  EXPECT_LT(op.flux_ratio, 0.7);
  EXPECT_NEAR(op.magnetizing_current_a, m.magnetizing_current_a * op.flux_ratio, 1e-9);
  // The voltage stays at the rated level instead of rising with frequency.
  EXPECT_NEAR(op.voltage_v, m.rated_voltage_v, 0.05 * m.rated_voltage_v);
  // Same torque needs more rotor current in a weaker field.
  const double t_same = 0.8 * rated_torque_nm(m);
  const OperatingPoint below = operating_point(m, 0.8 * base_speed_rpm(m), t_same, 100.0, 100.0);
  const OperatingPoint above = operating_point(m, 1.8 * base_speed_rpm(m), t_same, 100.0, 100.0);
  EXPECT_GT(above.rotor_current_a, 1.5 * below.rotor_current_a);
}

TEST(OperatingPoint, BrakingRunsBelowRotorFrequencyAndHeatsTheRotor) {
  const MotorSpec m = example_motor();
  for (const double n : {600.0, 1900.0, 3200.0}) {
    const double t = -torque_limit_nm(m, n);
    const OperatingPoint op = operating_point(m, n, t, 100.0, 100.0);
    ASSERT_TRUE(op.pulses_on);
    EXPECT_LT(op.frequency_hz, mech_frequency_hz(m, n));
    EXPECT_LT(op.slip_hz, 0.0);
    EXPECT_GT(op.rotor_copper_w, 0.0);
    // Generating: the R1 drop now subtracts from the EMF, so less voltage than motoring.
    EXPECT_LT(op.voltage_v, operating_point(m, n, -t, 100.0, 100.0).voltage_v);
  }
}

TEST(OperatingPoint, ReverseRunningIsTheMirrorImage) {
  const MotorSpec m = example_motor();
  for (const double n : {400.0, 2500.0}) {
    for (const double t : {900.0, -900.0}) {
      const OperatingPoint fwd = operating_point(m, n, t, 90.0, 70.0);
      const OperatingPoint rev = operating_point(m, -n, -t, 90.0, 70.0);
      EXPECT_NEAR(rev.frequency_hz, -fwd.frequency_hz, 1e-9);
      EXPECT_NEAR(rev.slip_hz, -fwd.slip_hz, 1e-9);
      EXPECT_NEAR(rev.current_a, fwd.current_a, 1e-9);
      EXPECT_NEAR(rev.voltage_v, fwd.voltage_v, 1e-9);
      EXPECT_NEAR(rev.rotor_copper_w, fwd.rotor_copper_w, 1e-9);
    }
  }
}

TEST(OperatingPoint, PulsesOffBelowOnePercentTorque) {
  const MotorSpec m = example_motor();
  const double tr = rated_torque_nm(m);
  const OperatingPoint idle = operating_point(m, 1200.0, 0.005 * tr, 60.0, 60.0);
  EXPECT_FALSE(idle.pulses_on);
  EXPECT_EQ(idle.current_a, 0.0);
  EXPECT_EQ(idle.voltage_v, 0.0);
  EXPECT_EQ(idle.rotor_copper_w, 0.0);
  EXPECT_DOUBLE_EQ(idle.frequency_hz, mech_frequency_hz(m, 1200.0));
  const OperatingPoint standing = operating_point(m, 0.0, 0.0, 60.0, 60.0);
  EXPECT_FALSE(standing.pulses_on);
  EXPECT_EQ(standing.frequency_hz, 0.0);
  const OperatingPoint light = operating_point(m, 1200.0, -0.02 * tr, 60.0, 60.0);
  EXPECT_TRUE(light.pulses_on);
  EXPECT_NEAR(light.current_a, m.magnetizing_current_a, 5.0);
}

TEST(OperatingPoint, HotStatorNeedsMoreVoltage) {
  const MotorSpec m = example_motor();
  const double t = rated_torque_nm(m);
  const OperatingPoint cold = operating_point(m, 800.0, t, 80.0, 20.0);
  const OperatingPoint hot = operating_point(m, 800.0, t, 80.0, 160.0);
  EXPECT_GT(hot.voltage_v, cold.voltage_v);
  EXPECT_DOUBLE_EQ(hot.current_a, cold.current_a);  // current does not depend on R1
}

TEST(OperatingPoint, EnvelopeStaysWithinConverterLimits) {
  const MotorSpec m = example_motor();
  double peak_current = 0.0;
  for (double n = 0.0; n <= max_speed_rpm(m); n += 25.0) {
    for (const double sign : {1.0, -1.0}) {
      const OperatingPoint op = operating_point(m, n, sign * torque_limit_nm(m, n), 180.0, 180.0);
      EXPECT_LE(op.voltage_v, kMaxVoltageFactor * m.rated_voltage_v + 1e-9) << n;
      EXPECT_GT(op.flux_ratio, 0.4) << n;
      peak_current = std::max(peak_current, op.current_a);
    }
  }
  // Peak torque costs well above rated current, but not absurdly so.
  EXPECT_GT(peak_current, 1.2 * m.rated_current_a);
  EXPECT_LT(peak_current, 1.6 * m.rated_current_a);
}

}  // namespace
}  // namespace lptn::plant
