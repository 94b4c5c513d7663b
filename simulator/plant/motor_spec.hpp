#pragma once
// Nameplate of the traction induction motor the synthetic plant drives, and the quantities
// derived from it that both the operating-point model and the driving-cycle generator need.

#include <cmath>
#include <numbers>

#include "lptn/nameplate.hpp"

namespace lptn::plant {

// A plain aggregate the caller fills from the motor file: its nameplate, then the electrical
// constants. Resistances are per phase, the rotor's referred to the stator.
struct MotorSpec : Nameplate<double> {
  double stator_resistance_20c_ohm;
  double stator_resistance_alpha_per_k;
  double rotor_resistance_20c_ohm;
  double rotor_resistance_alpha_per_k;
  double magnetizing_current_a;
  double max_torque_factor = 1.6;  // peak (starting) torque / rated torque
  double max_speed_factor = 2.1;   // top motor speed / base speed
};

// Where the constant-power region of the envelope ends (as a multiple of base speed); beyond it
// the converter's voltage limit makes the torque fall as 1/n^2 (power as 1/n).
inline constexpr double kConstantPowerEndFactor = 1.6;

// Base speed: synchronous speed at rated frequency. The slip at rated load is < 1 % of it, so
// using the synchronous speed keeps the helpers independent of temperature.
inline double base_speed_rpm(const MotorSpec& m) { return m.base_speed_rpm(); }

inline double max_speed_rpm(const MotorSpec& m) { return m.max_speed_factor * base_speed_rpm(m); }

// Rated (continuous) torque: rated power at base speed.
inline double rated_torque_nm(const MotorSpec& m) {
  return m.rated_power_w / (2.0 * std::numbers::pi * base_speed_rpm(m) / 60.0);
}

inline double rated_phase_voltage_v(const MotorSpec& m) {
  return m.rated_voltage_v / std::numbers::sqrt3;
}

// Per-phase RMS stator flux linkage at rated voltage and frequency (leakage neglected).
inline double rated_flux_linkage_wb(const MotorSpec& m) {
  return rated_phase_voltage_v(m) / (2.0 * std::numbers::pi * m.rated_frequency_hz);
}

inline double stator_resistance_ohm(const MotorSpec& m, double temp_c) {
  return m.stator_resistance_20c_ohm * (1.0 + m.stator_resistance_alpha_per_k * (temp_c - 20.0));
}

inline double rotor_resistance_ohm(const MotorSpec& m, double temp_c) {
  return m.rotor_resistance_20c_ohm * (1.0 + m.rotor_resistance_alpha_per_k * (temp_c - 20.0));
}

// Largest |torque| the drive delivers at a speed, motoring and braking alike: constant torque up
// to base speed, constant power up to kConstantPowerEndFactor x base, then falling as 1/n^2.
// Symmetric in the sign of the speed. Not cut off above max speed (the cycles never get there).
inline double torque_limit_nm(const MotorSpec& m, double speed_rpm) {
  const double t_max = m.max_torque_factor * rated_torque_nm(m);
  const double n = std::abs(speed_rpm);
  const double n_base = base_speed_rpm(m);
  const double n_cp = kConstantPowerEndFactor * n_base;
  if (n <= n_base) return t_max;
  if (n <= n_cp) return t_max * n_base / n;
  return t_max * n_base * n_cp / (n * n);
}

}  // namespace lptn::plant
