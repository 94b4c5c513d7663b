// Shared fixtures for the model tests: the example motor and a reference operating point.
#pragma once

#include "lptn/model.hpp"

namespace lptn::testing {

inline MotorConstants<double> example_motor() {
  MotorConstants<double> m;  // defaults are the contract's example motor
  const double f[] = {0.0, 10.0, 30.0, 65.0, 140.0};
  const double p[] = {1100.0, 1400.0, 1700.0, 1400.0, 900.0};
  m.harmonic_points = 5;
  for (int i = 0; i < 5; ++i) {
    m.harmonic_frequency_hz[i] = f[i];
    m.harmonic_loss_w[i] = p[i];
  }
  return m;
}

// Rated point: 1930 rpm, rated torque, consistent current, frequency and voltage.
inline Inputs<double> rated_inputs() {
  Inputs<double> in;
  in.speed_rpm = 1930.0;
  in.torque_nm = 1530.0;
  in.current_a = 103.0;
  in.frequency_hz = 64.9;
  in.voltage_v = 1895.0;
  in.airflow_m3s = 1.0;
  in.ambient_c = 25.0;
  in.has_torque = true;
  in.has_voltage = true;
  return in;
}

}  // namespace lptn::testing
