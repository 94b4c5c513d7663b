// A traction converter for the tests: sends the DBC's input frames at their cycle times, with
// alive counters, through the generated encoders; and a drive profile with a thermal truth (the
// model itself with chosen parameters) for the stator sensor to read.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

#include "lptn/can/lptn_frames.hpp"
#include "lptn/firmware/can_frame.hpp"
#include "lptn/firmware/input.hpp"
#include "lptn/model.hpp"
#include "lptn_testing/reference_case.hpp"

namespace lptn::fw::testing {

struct DriveState {
  double speed_rpm = 0, torque_nm = 0, current_a = 0, frequency_hz = 0, voltage_v = 0;
  double airflow_m3s = 1, ambient_c = 20;
  double stator_c = 20, rotor_c = 20;
};

using lptn::testing::example_motor;  // the contract's example motor (tests/common)

// A repeating 20-minute duty: accelerate, cruise, brake, stand; the blower follows the load.
inline DriveState drive_at(double t_s) {
  DriveState s;
  const double phase = std::fmod(t_s, 1200.0);
  s.speed_rpm = phase < 200 ? 9.0 * phase : (phase < 800 ? 1800.0 : (phase < 1000 ? 1800.0 - 9.0 * (phase - 800) : 0.0));
  const bool standing = phase >= 1000;
  s.torque_nm = phase < 200 ? 2200.0 : (phase < 800 ? 700.0 : (phase < 1000 ? -1500.0 : 0.0));
  s.current_a = standing ? 0.0 : 35.0 + 0.05 * std::abs(s.torque_nm);
  s.frequency_hz = standing ? 0.0 : 2.0 * s.speed_rpm / 60.0 + s.torque_nm * 0.0004;
  s.voltage_v = std::min(1900.0, 29.2 * std::abs(s.frequency_hz));
  s.airflow_m3s = standing ? 0.3 : (std::abs(s.torque_nm) > 1000 ? 1.0 : 0.6);
  s.ambient_c = 22.0 + 3.0 * std::sin(t_s / 3000.0);
  return s;
}

// The model's inputs as the estimator decodes them from the frames (quantized by the DBC).
inline Inputs<double> decoded_inputs(const DriveState& s, bool torque, bool voltage) {
  using namespace can;
  Inputs<double> in;
  in.speed_rpm = TcElectrical::motor_speed_decode(TcElectrical::motor_speed_encode(s.speed_rpm));
  in.frequency_hz = TcElectrical::stator_frequency_decode(TcElectrical::stator_frequency_encode(s.frequency_hz));
  in.current_a = TcElectrical::stator_current_decode(TcElectrical::stator_current_encode(s.current_a));
  in.airflow_m3s = TcCooling::cooling_airflow_decode(TcCooling::cooling_airflow_encode(s.airflow_m3s));
  in.ambient_c = TcCooling::ambient_temp_decode(TcCooling::ambient_temp_encode(s.ambient_c));
  in.has_torque = torque;
  in.torque_nm = torque ? TcTorque::motor_torque_decode(TcTorque::motor_torque_encode(s.torque_nm)) : 0.0;
  in.has_voltage = voltage;
  in.voltage_v = voltage ? TcVoltage::stator_voltage_decode(TcVoltage::stator_voltage_encode(s.voltage_v)) : 0.0;
  return in;
}

class Converter {
 public:
  bool send_torque = true, send_voltage = true, send_rotor = false;
  bool send_electrical = true, send_cooling = true, send_stator = true;

  CanFrame electrical(const DriveState& s) {
    can::TcElectrical m;
    m.motor_speed = can::TcElectrical::motor_speed_encode(s.speed_rpm);
    m.stator_frequency = can::TcElectrical::stator_frequency_encode(s.frequency_hz);
    m.stator_current = can::TcElectrical::stator_current_encode(s.current_a);
    m.pulses_enabled = s.current_a > 0.5 ? 1 : 0;
    m.alive_counter = next(0);
    return to_frame(m);
  }
  CanFrame torque(const DriveState& s) {
    can::TcTorque m;
    m.motor_torque = can::TcTorque::motor_torque_encode(s.torque_nm);
    m.alive_counter = next(1);
    return to_frame(m);
  }
  CanFrame voltage(const DriveState& s) {
    can::TcVoltage m;
    m.stator_voltage = can::TcVoltage::stator_voltage_encode(s.voltage_v);
    m.alive_counter = next(2);
    return to_frame(m);
  }
  CanFrame cooling(const DriveState& s) {
    can::TcCooling m;
    m.cooling_airflow = can::TcCooling::cooling_airflow_encode(s.airflow_m3s);
    m.ambient_temp = can::TcCooling::ambient_temp_encode(s.ambient_c);
    m.alive_counter = next(3);
    return to_frame(m);
  }
  CanFrame stator(double reading_c) {
    can::TcStatorTemp m;
    m.stator_winding_temp = can::TcStatorTemp::stator_winding_temp_encode(reading_c);
    m.alive_counter = next(4);
    return to_frame(m);
  }
  CanFrame rotor(double reading_c) {
    can::BenchRotorTemp m;
    m.rotor_temp = can::BenchRotorTemp::rotor_temp_encode(reading_c);
    m.alive_counter = next(5);
    return to_frame(m);
  }

  // The frames due at time t (a multiple of 100 ms): 100 ms messages every call, 1 s ones every
  // tenth. emit(frame) for each.
  template <class Emit>
  void frames_at(TimeUs t, const DriveState& s, Emit&& emit) {
    if (send_electrical) emit(electrical(s));
    if (send_torque) emit(torque(s));
    if (send_voltage) emit(voltage(s));
    if (t % kUsPerS == 0) {
      if (send_cooling) emit(cooling(s));
      if (send_stator) emit(stator(s.stator_c));
      if (send_rotor) emit(rotor(s.rotor_c));
    }
  }

  std::uint8_t counter[6]{};

 private:
  std::uint8_t next(int message) {
    const std::uint8_t c = counter[message];
    counter[message] = static_cast<std::uint8_t>((c + 1) & 0xF);
    return c;
  }
};

// The thermal truth: the model with its own parameters, stepped on the exact (unquantized)
// inputs, read by a noisy 0.1 K-quantized sensor.
class Plant {
 public:
  Plant(const ParamVector<double>& params, double start_c, unsigned seed = 1)
      : model_(example_motor(), 0), params_(params), rng_(seed) {
    model_.initial_state(x_, start_c, start_c);
  }
  void step(const DriveState& s) {
    Inputs<double> in;
    in.speed_rpm = s.speed_rpm;
    in.torque_nm = s.torque_nm;
    in.current_a = s.current_a;
    in.frequency_hz = s.frequency_hz;
    in.voltage_v = s.voltage_v;
    in.airflow_m3s = s.airflow_m3s;
    in.ambient_c = s.ambient_c;
    in.has_torque = in.has_voltage = true;
    model_.step(x_, in, params_.data(), 0.1);
  }
  double node(int i) const { return x_[i]; }
  double sensor_reading() {
    std::normal_distribution<double> noise(0.0, noise_k);
    return std::round((x_[kStatorWinding] + noise(rng_)) * 10.0) / 10.0;
  }
  double noise_k = 0.4;

 private:
  Model<double> model_;
  ParamVector<double> params_;
  double x_[kMaxStates]{};
  std::mt19937 rng_;
};

// The example motor's true conductances (as the synthetic plant of `lptn generate` has them).
inline ParamVector<double> true_params() {
  ParamVector<double> p = default_params<double>();
  p[kLambda1s] = 24;
  p[kLambda2s] = 65;
  p[kLambda12s] = 110;
  p[kLambda1r] = 21;
  p[kLambda2r] = 45;
  p[kLambda12r] = 150;
  return p;
}

}  // namespace lptn::fw::testing
