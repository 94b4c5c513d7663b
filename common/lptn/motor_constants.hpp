// What the user knows about the motor from nameplate, geometry and bench tests: the constants of
// the paper's loss model and thermal network that calibration does not move.
#pragma once

namespace lptn {

inline constexpr int kMaxHarmonicPoints = 16;

template <class R>
struct MotorConstants {
  // [nameplate]
  int pole_pairs = 2;
  R rated_frequency_hz = R(65);
  R rated_voltage_v = R(1900);  // line, RMS
  R rated_current_a = R(115);   // phase, RMS
  R rated_power_w = R(310e3);
  // [electrical]
  R stator_resistance_20c_ohm = R(0.14);  // per phase
  R stator_resistance_alpha_per_k = R(0.00393);
  R rotor_resistance_20c_ohm = R(0.10);  // referred to the stator
  R rotor_resistance_alpha_per_k = R(0.0039);
  R magnetizing_current_a = R(40);  // at rated flux
  // [losses]
  R stray_rated_w = R(1400);  // eq. 11 at rated frequency and current
  R iron_rated_w = R(2800);   // eq. 12 at rated frequency and flux
  R iron_alpha = R(1.5);
  R iron_beta = R(2.0);
  int harmonic_points = 0;  // eq. 13's look-up table over stator frequency
  R harmonic_frequency_hz[kMaxHarmonicPoints] = {};
  R harmonic_loss_w[kMaxHarmonicPoints] = {};
  // [thermal]
  R capacitance_j_per_k[4] = {R(38e3), R(240e3), R(22e3), R(110e3)};
  R nominal_airflow_m3s = R(1);
  R airflow_exponent = R(0.8);
  // Natural convection keeps some cooling when the blower stops; without a floor the conductances
  // to the air would vanish with the airflow and a standing motor could never cool.
  R min_airflow_fraction = R(0.1);

  R base_speed_rpm() const { return R(60) * rated_frequency_hz / R(pole_pairs); }

  template <class To>
  MotorConstants<To> cast() const {
    MotorConstants<To> c;
    c.pole_pairs = pole_pairs;
    c.rated_frequency_hz = To(rated_frequency_hz);
    c.rated_voltage_v = To(rated_voltage_v);
    c.rated_current_a = To(rated_current_a);
    c.rated_power_w = To(rated_power_w);
    c.stator_resistance_20c_ohm = To(stator_resistance_20c_ohm);
    c.stator_resistance_alpha_per_k = To(stator_resistance_alpha_per_k);
    c.rotor_resistance_20c_ohm = To(rotor_resistance_20c_ohm);
    c.rotor_resistance_alpha_per_k = To(rotor_resistance_alpha_per_k);
    c.magnetizing_current_a = To(magnetizing_current_a);
    c.stray_rated_w = To(stray_rated_w);
    c.iron_rated_w = To(iron_rated_w);
    c.iron_alpha = To(iron_alpha);
    c.iron_beta = To(iron_beta);
    c.harmonic_points = harmonic_points;
    for (int i = 0; i < kMaxHarmonicPoints; ++i) {
      c.harmonic_frequency_hz[i] = To(harmonic_frequency_hz[i]);
      c.harmonic_loss_w[i] = To(harmonic_loss_w[i]);
    }
    for (int i = 0; i < 4; ++i) c.capacitance_j_per_k[i] = To(capacitance_j_per_k[i]);
    c.nominal_airflow_m3s = To(nominal_airflow_m3s);
    c.airflow_exponent = To(airflow_exponent);
    c.min_airflow_fraction = To(min_airflow_fraction);
    return c;
  }
};

}  // namespace lptn
