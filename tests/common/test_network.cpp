// The four-node network, equations 1-6, against a system written out by hand, and its energy balance.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "lptn/model.hpp"
#include "lptn_testing/reference_case.hpp"

namespace lptn {
namespace {

// Equations 1-6 written out directly (G T = q at steady state), independent of HeatBalance and of
// the model's assembly code, with the copper losses' temperature dependence moved to G.
Eigen::Vector4d hand_steady_state(const MotorConstants<double>& m, const Inputs<double>& in, const ParamVector<double>& p) {
  const OperatingLosses<double> l = operating_losses(m, in);
  const double k = std::pow(in.airflow_m3s / m.nominal_airflow_m3s, m.airflow_exponent);
  const double l1s = p[kLambda1s] * k, l2s = p[kLambda2s] * k, l1r = p[kLambda1r] * k, l2r = p[kLambda2r] * k;
  const double l12s = p[kLambda12s], l12r = p[kLambda12r];
  const double a1 = m.stator_resistance_alpha_per_k, a2 = m.rotor_resistance_alpha_per_k;
  const double pcu1_20 = p[kKStemp] * l.stator_copper_20c_w;
  const double pcu2_20 = p[kKRtemp] * l.rotor_copper_20c_w;
  Eigen::Matrix4d g;
  g << l1s + l12s - pcu1_20 * a1, -l12s, 0, 0,  //
      -l12s, l2s + l12s, 0, 0,                  //
      0, 0, l1r + l12r - pcu2_20 * a2, -l12r,   //
      0, 0, -l12r, l2r + l12r;
  const double ta = in.ambient_c;
  Eigen::Vector4d q;
  q << pcu1_20 * (1 - 20 * a1) + p[kKStray] * l.stray_w + p[kKHarm] * l.harmonic_w + l1s * ta,
      p[kKPfe] * l.iron_w + l2s * ta,
      pcu2_20 * (1 - 20 * a2) + (1 - p[kKStray]) * l.stray_w + (1 - p[kKHarm]) * l.harmonic_w + l1r * ta,
      (1 - p[kKPfe]) * l.iron_w + l2r * ta;
  q[2] += p[kKRtemp] * l.rotor_copper_w;  // zero unless the slip-power route was taken
  return g.partialPivLu().solve(q);
}

TEST(Network, SteadyStateMatchesTheEquationsSolvedByHand) {
  const auto m = testing::example_motor();
  const Model<double> model(m, 0);
  // With torque on the bus the rotor copper loss is the slip power; without, it comes from I21
  // and grows with the rotor temperature.
  for (bool torque_on_bus : {true, false}) {
    Inputs<double> in = testing::rated_inputs();
    in.has_torque = torque_on_bus;
    in.airflow_m3s = 0.7;
    ParamVector<double> p = default_params<double>();
    p[kLambda12s] = 300.0;
    p[kKStray] = 0.4;
    double x[kMaxStates];
    model.initial_state(x, 25.0, 25.0);
    for (int k = 0; k < 40 * 3600; ++k) model.step(x, in, p.data(), 1.0);  // 40 h: settled
    const Eigen::Vector4d expected = hand_steady_state(m, in, p);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(x[i], expected[i], 1e-6) << "node " << i + 1 << " torque " << torque_on_bus;
    EXPECT_GT(x[0], 100.0);  // a real load case, not a trivially cold one
  }
}

// Internal paths only move heat: summed over the nodes, C dT/dt equals the losses minus the heat
// given to the air, whatever the state. Checked for the paper's model and with every effect that
// keeps the nodes' energy bookkeeping (air_heating moves heat already given to the air; a sensor
// state is not a thermal node).
TEST(Network, InternalPathsConserveEnergy) {
  const auto m = testing::example_motor();
  const EffectSet conserving = effect_bit(effect_index("airgap")) | effect_bit(effect_index("windage")) |
                               effect_bit(effect_index("rotor_speed_convection"));
  for (EffectSet effects : {EffectSet{0}, conserving}) {
    const Model<double> model(m, effects);
    const ParamVector<double> p = default_params<double>();
    const Inputs<double> in = testing::rated_inputs();
    const double x[kMaxStates] = {140.0, 95.0, 160.0, 120.0};
    HeatBalance<double> sys;
    const OperatingLosses<double> l = model.assemble(in, p.data(), sys);
    double stored = 0;
    for (int i = 0; i < 4; ++i) stored += sys.capacitance[i] * sys.derivative(i, x);
    const double r1 = 1 + m.stator_resistance_alpha_per_k * (x[0] - 20);
    double losses = p[kKStemp] * l.stator_copper_20c_w * r1 + p[kKRtemp] * l.rotor_copper_w + l.stray_w + l.iron_w +
                    l.harmonic_w;
    const double speed_ratio = in.speed_rpm / m.base_speed_rpm();
    double rotor_gain = 1.0;
    if (effects != 0) {
      losses += p[param_index("windage_base_w")] * speed_ratio * speed_ratio;
      rotor_gain = 1 + p[param_index("rotor_convection_gain")] * speed_ratio;
    }
    const double k = airflow_factor(m, in.airflow_m3s);
    const double to_air = k * (p[kLambda1s] * (x[0] - in.ambient_c) + p[kLambda2s] * (x[1] - in.ambient_c) +
                               rotor_gain * (p[kLambda1r] * (x[2] - in.ambient_c) + p[kLambda2r] * (x[3] - in.ambient_c)));
    EXPECT_NEAR(stored, losses - to_air, 1e-9 * losses) << "effects " << effects;
  }
}

// Over an hour of changing load, the energy stored in the nodes equals the integral of losses
// minus heat to air (trapezoid over a fine step).
TEST(Network, EnergyBalanceHoldsOverAChangingCycle) {
  const auto m = testing::example_motor();
  const Model<double> model(m, 0);
  const ParamVector<double> p = default_params<double>();
  double x[kMaxStates];
  model.initial_state(x, 30.0, 30.0);
  const double dt = 0.01;
  double stored0 = 0;
  for (int i = 0; i < 4; ++i) stored0 += m.capacitance_j_per_k[i] * x[i];
  double inflow = 0, previous = 0;
  for (int k = 0; k <= 360000; ++k) {
    Inputs<double> in = testing::rated_inputs();
    const double t = k * dt;
    in.current_a = 60 + 50 * std::sin(t / 300.0);
    in.airflow_m3s = 0.6 + 0.3 * std::cos(t / 700.0);
    in.has_torque = false;
    HeatBalance<double> sys;
    model.assemble(in, p.data(), sys);
    double now = 0;
    for (int i = 0; i < 4; ++i) now += sys.capacitance[i] * sys.derivative(i, x);
    if (k > 0) inflow += 0.5 * (now + previous) * dt;
    previous = now;
    if (k < 360000) Sdirk2<double>::step(sys, x, dt);
  }
  double stored1 = 0;
  for (int i = 0; i < 4; ++i) stored1 += m.capacitance_j_per_k[i] * x[i];
  EXPECT_NEAR(stored1 - stored0, inflow, 1e-4 * std::abs(inflow));
  EXPECT_GT(stored1 - stored0, 1e6);  // the cycle did heat the motor
}

}  // namespace
}  // namespace lptn
