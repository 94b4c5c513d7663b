#include "simulator/plant/operating_point.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace lptn::plant {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Stator frequency and flux linkage for a mechanical frequency and torque.
// At rated flux the slip (Hz) is s0 = T R2 / (3 p Psi_r^2 2 pi). In field weakening Psi falls as
// f_base / |f|, so the slip becomes s0 (f / f_base)^2 and f = f_mech + k f^2 with k = s0 / f_base^2.
// Its root nearer f_mech, written to stay exact for k -> 0 and for either sign, is
// f = 2 f_mech / (1 + sqrt(1 - 4 k f_mech)). The discriminant only goes negative far beyond the
// torque envelope (pull-out of this leakage-free machine); it is clamped there.
struct StatorField {
  double frequency_hz;
  double flux_wb;
};

StatorField stator_field(double f_mech, double slip_rated_flux_hz, double f_base, double psi_rated) {
  const double f_const_flux = f_mech + slip_rated_flux_hz;
  if (std::abs(f_const_flux) <= f_base) return {f_const_flux, psi_rated};
  const double k = slip_rated_flux_hz / (f_base * f_base);
  const double disc = std::max(0.0, 1.0 - 4.0 * k * f_mech);
  const double f = 2.0 * f_mech / (1.0 + std::sqrt(disc));
  return {f, psi_rated * f_base / std::abs(f)};
}

}  // namespace

OperatingPoint operating_point(const MotorSpec& motor, double speed_rpm, double torque_nm,
                               double rotor_temp_c, double stator_temp_c) {
  const double p = motor.pole_pairs;
  const double f_mech = p * speed_rpm / 60.0;

  if (std::abs(torque_nm) < kPulsesOffTorqueFraction * rated_torque_nm(motor)) {
    // Converter idle and the machine demagnetised; the drive still reports the rotor frequency.
    return OperatingPoint{.current_a = 0.0,
                          .frequency_hz = f_mech,
                          .voltage_v = 0.0,
                          .slip_hz = 0.0,
                          .flux_ratio = 0.0,
                          .magnetizing_current_a = 0.0,
                          .rotor_current_a = 0.0,
                          .rotor_copper_w = 0.0,
                          .pulses_on = false};
  }

  const double r1 = stator_resistance_ohm(motor, stator_temp_c);
  const double r2 = rotor_resistance_ohm(motor, rotor_temp_c);
  const double psi_rated = rated_flux_linkage_wb(motor);

  const double slip_rated_flux_hz = torque_nm * r2 / (3.0 * p * psi_rated * psi_rated) / kTwoPi;
  const StatorField field = stator_field(f_mech, slip_rated_flux_hz, motor.rated_frequency_hz, psi_rated);
  const double psi = field.flux_wb;
  const double slip_hz = field.frequency_hz - f_mech;
  const double omega_r = kTwoPi * slip_hz;

  // Rotor branch is purely resistive without leakage: I2 in phase with the air-gap EMF, and
  // 3 I2^2 R2 = T w_r / p (the slip power) identically.
  const double i2 = psi * omega_r / r2;
  const double im = motor.magnetizing_current_a * psi / psi_rated;
  const double i1 = std::hypot(im, i2);

  // Phasors relative to the EMF E: the active (rotor) current is along E, positive when air-gap
  // power T * 2 pi f / p flows into the rotor; the magnetising current lags E by 90 degrees.
  // V = E + R1 I1 exactly for this circuit: |V| = sqrt((E + R1 I_act)^2 + (R1 Im)^2).
  // The converter caps the line voltage at kMaxVoltageFactor x rated at every frequency (a cap
  // proportional to f below base would clip the genuine R1 drop at low frequency); within the
  // torque envelope the cap is not reached.
  const double emf = kTwoPi * std::abs(field.frequency_hz) * psi;
  const double airgap_power_sign = (torque_nm * field.frequency_hz >= 0.0) ? 1.0 : -1.0;
  const double i_active = airgap_power_sign * std::abs(i2);
  const double v_phase = std::hypot(emf + r1 * i_active, r1 * im);
  const double v_line =
      std::min(std::numbers::sqrt3 * v_phase, kMaxVoltageFactor * motor.rated_voltage_v);

  return OperatingPoint{.current_a = i1,
                        .frequency_hz = field.frequency_hz,
                        .voltage_v = v_line,
                        .slip_hz = slip_hz,
                        .flux_ratio = psi / psi_rated,
                        .magnetizing_current_a = im,
                        .rotor_current_a = std::abs(i2),
                        .rotor_copper_w = 3.0 * i2 * i2 * r2,
                        .pulses_on = true};
}

}  // namespace lptn::plant
