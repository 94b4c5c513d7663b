#pragma once
// Steady-state electrical operating point of the induction motor for a mechanical demand
// (speed, torque) and the winding temperatures: what the converter would report.

#include "simulator/plant/motor_spec.hpp"

namespace lptn::plant {

struct OperatingPoint {
  double current_a;              // stator phase RMS
  double frequency_hz;           // stator (converter) frequency; negative when the field turns backwards
  double voltage_v;              // line RMS at the motor terminals
  double slip_hz;                // frequency_hz - pole_pairs * speed / 60 (sign of the torque)
  double flux_ratio;             // stator flux linkage / rated (0 with pulses off)
  double magnetizing_current_a;  // phase RMS
  double rotor_current_a;        // referred to the stator, phase RMS
  double rotor_copper_w;         // 3 * I2^2 * R2(T_rotor)
  bool pulses_on;
};

// Below this |torque| (fraction of rated) the converter is idle: coasting or standing.
inline constexpr double kPulsesOffTorqueFraction = 0.01;

// Highest line voltage the converter can put out, as a multiple of rated.
inline constexpr double kMaxVoltageFactor = 1.05;

// Model: linear magnetics, leakage neglected. Flux linkage rated up to base frequency, then
// Psi_rated * f_base / |f|. Slip w_r = T R2 / (3 p Psi^2), f = p n / 60 + w_r / 2pi (solved jointly
// with the flux in field weakening), I2 = Psi w_r / R2, Im = Im_rated Psi / Psi_rated,
// I1 = sqrt(Im^2 + I2^2), V_phase = |E + R1 I1| with E = 2 pi |f| Psi (see the .cpp).
// Speeds and torques of any sign; reverse running follows by symmetry.
OperatingPoint operating_point(const MotorSpec& motor, double speed_rpm, double torque_nm,
                               double rotor_temp_c, double stator_temp_c);

}  // namespace lptn::plant
