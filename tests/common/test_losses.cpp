// The loss model, equations 7-13, against hand calculations.
#include <gtest/gtest.h>

#include <cmath>

#include "lptn/paper_model.hpp"
#include "lptn_testing/reference_case.hpp"

namespace lptn {
namespace {

using testing::example_motor;
constexpr double kPi = 3.141592653589793;

TEST(Losses, StatorCopperIsThreeRI2AtTwentyDegrees) {
  const auto m = example_motor();
  Inputs<double> in = testing::rated_inputs();
  in.current_a = 100.0;
  EXPECT_DOUBLE_EQ(operating_losses(m, in).stator_copper_20c_w, 3 * 0.14 * 100.0 * 100.0);
}

// A steady operating point built from the induction machine's equations (flux at rated, slip from
// torque and rotor resistance): the slip-power route and the rotor-current route must agree.
TEST(Losses, SlipPowerAndRotorCurrentRoutesAgree) {
  const auto m = example_motor();
  const double psi = m.rated_voltage_v / std::sqrt(3.0) / (2 * kPi * m.rated_frequency_hz);
  for (double torque : {300.0, 900.0, 1530.0, 2400.0}) {
    const double speed = 1500.0;
    const double p = m.pole_pairs;
    const double w_r = torque * m.rotor_resistance_20c_ohm / (3 * p * psi * psi);
    const double i2 = psi * w_r / m.rotor_resistance_20c_ohm;
    const double i1 = std::hypot(m.magnetizing_current_a, i2);
    const double f = p * speed / 60 + w_r / (2 * kPi);
    Inputs<double> in;
    in.speed_rpm = speed;
    in.torque_nm = torque;
    in.current_a = i1;
    in.frequency_hz = f;
    in.voltage_v = std::sqrt(3.0) * 2 * kPi * f * psi;
    in.has_voltage = true;
    in.has_torque = true;
    const auto slip = operating_losses(m, in);
    in.has_torque = false;
    const auto current = operating_losses(m, in);
    ASSERT_EQ(slip.rotor_route, RotorLossRoute::slip_power);
    ASSERT_EQ(current.rotor_route, RotorLossRoute::rotor_current);
    EXPECT_NEAR(slip.rotor_copper_w, current.rotor_copper_20c_w, 1e-9 * slip.rotor_copper_w) << torque;
    EXPECT_NEAR(slip.rotor_copper_w, 3 * i2 * i2 * m.rotor_resistance_20c_ohm, 1e-9 * slip.rotor_copper_w);
  }
}

TEST(Losses, SlipPowerIsPositiveWhenBraking) {
  const auto m = example_motor();
  Inputs<double> in = testing::rated_inputs();
  in.torque_nm = -1200.0;
  in.frequency_hz = 2 * in.speed_rpm / 60 - 0.5;  // generator: below synchronous
  const auto l = operating_losses(m, in);
  EXPECT_NEAR(l.rotor_copper_w, 1200.0 * 2 * kPi * 0.5 / 2, 1e-9);
}

TEST(Losses, StrayLossFollowsEquation11) {
  const auto m = example_motor();
  Inputs<double> in = testing::rated_inputs();
  in.frequency_hz = m.rated_frequency_hz;
  in.current_a = m.rated_current_a;
  EXPECT_NEAR(operating_losses(m, in).stray_w, m.stray_rated_w, 1e-9);
  in.frequency_hz = m.rated_frequency_hz / 2;
  in.current_a = m.rated_current_a / 2;
  EXPECT_NEAR(operating_losses(m, in).stray_w, m.stray_rated_w * std::pow(0.5, 1.5) * 0.25, 1e-9);
}

TEST(Losses, IronLossFollowsFluxFromVoltageOrNominalProfile) {
  const auto m = example_motor();
  Inputs<double> in = testing::rated_inputs();
  in.frequency_hz = 130.0;  // twice rated: field weakening, flux halves
  in.voltage_v = m.rated_voltage_v;
  const double expected = m.iron_rated_w * std::pow(2.0, 1.5) * 0.25;
  EXPECT_NEAR(operating_losses(m, in).flux_ratio, 0.5, 1e-12);
  EXPECT_NEAR(operating_losses(m, in).iron_w, expected, 1e-9);
  in.has_voltage = false;  // nominal V/f profile gives the same at this point
  EXPECT_NEAR(operating_losses(m, in).iron_w, expected, 1e-9);
  in.has_voltage = true;  // a converter running at 80 % voltage: flux and iron loss drop
  in.voltage_v = 0.8 * m.rated_voltage_v;
  EXPECT_NEAR(operating_losses(m, in).iron_w, expected * 0.64, 1e-9);
}

TEST(Losses, HarmonicTableInterpolatesAndHoldsItsEnds) {
  const auto m = example_motor();
  EXPECT_DOUBLE_EQ(harmonic_loss(m, 0.0), 1100.0);
  EXPECT_DOUBLE_EQ(harmonic_loss(m, 20.0), 1550.0);
  EXPECT_DOUBLE_EQ(harmonic_loss(m, 102.5), 1150.0);
  EXPECT_DOUBLE_EQ(harmonic_loss(m, 500.0), 900.0);
}

TEST(Losses, PulsesOffMeansNoFluxNoIronNoStrayNoHarmonicLoss) {
  const auto m = example_motor();
  Inputs<double> in = testing::rated_inputs();
  in.current_a = 0.0;
  in.torque_nm = 0.0;
  const auto l = operating_losses(m, in);
  EXPECT_FALSE(l.pulses_on);
  EXPECT_EQ(l.iron_w, 0.0);
  EXPECT_EQ(l.stray_w, 0.0);
  EXPECT_EQ(l.harmonic_w, 0.0);
  EXPECT_EQ(l.rotor_copper_w, 0.0);
  EXPECT_EQ(l.stator_copper_20c_w, 0.0);
}

TEST(Losses, ConductancesToAirScaleWithAirflowAndKeepAFloor) {
  const auto m = example_motor();
  EXPECT_DOUBLE_EQ(airflow_factor(m, 1.0), 1.0);
  EXPECT_NEAR(airflow_factor(m, 0.5), std::pow(0.5, 0.8), 1e-15);
  EXPECT_NEAR(airflow_factor(m, 0.0), std::pow(m.min_airflow_fraction, 0.8), 1e-15);
}

}  // namespace
}  // namespace lptn
