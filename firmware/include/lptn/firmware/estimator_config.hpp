// Everything the estimator is built from: the calibrated model, the observer's noise settings,
// the sensor monitor, each input's limits and the nodes' temperature limits. Filled once at
// start-up (default_config() for the documented defaults), then held by value: no heap.
#pragma once

#include "lptn/actor.hpp"
#include "lptn/bus/bus_glue.hpp"
#include "lptn/firmware/bus_decoder.hpp"
#include "lptn/firmware/cooling_alarm.hpp"
#include "lptn/firmware/input_conditioner.hpp"
#include "lptn/firmware/observer.hpp"
#include "lptn/firmware/sensor_monitor.hpp"
#include "lptn/grace_periods.hpp"
#include "lptn/model.hpp"

namespace lptn::fw {

// The frozen TD3 actor of an exported calibration (lptn export --actor): the parameters it drives
// follow speed and torque, obs = ((speed_rpm, torque_nm) - obs_offset) / obs_scale.
struct ActorSchedule {
  const ActorView* actor = nullptr;
  double obs_offset[2] = {0, 0};
  double obs_scale[2] = {1, 1};
  const int* param_index = nullptr;  // outputs() entries each
  const double* param_min = nullptr;
  const double* param_max = nullptr;
  int outputs() const { return actor ? actor->outputs : 0; }
};

template <class T>
struct EstimatorConfig {
  MotorConstants<T> motor{};
  EffectSet effects = 0;
  BusDecoder bus{};         // the converter's frames (the bus map's decoder)
  ParamVector<T> params{};  // the constant set (model order)
  ActorSchedule actor{};
  bool use_actor = false;  // schedule the actor's parameters (needs torque on the bus)
  bool fuse_stator_sensor = true;  // false: open loop
  ObserverSettings<T> observer{};  // observer.estimate_cooling: the cooling factor state
  CoolingAlarmSettings<T> cooling_alarm{};
  SensorMonitorSettings<T> sensor{};
  InputLimits<T> inputs[kNumInputs]{};
  // Insulation limits per node (class H winding, 180 C; the cage and core by their materials).
  T node_limit_c[kNumNodes] = {T(180), T(180), T(200), T(200)};
  // Without a stator reading the observer waits this long, then starts every node at
  // start_without_sensor_c with a wide uncertainty (a motor that may have just run).
  TimeUs start_without_sensor_after_us = 30 * kUsPerS;
  T start_without_sensor_c = T(120);
};

namespace internal {

// An input's freshness timeout: 3 cycle times of its message (1 s for an input not on the bus,
// which never arrives).
constexpr TimeUs timeout_us(const BusDecoder& bus, Input i) {
  const std::uint32_t cycle_ms = bus.input_cycle_ms[index_of(i)];
  return 3 * static_cast<TimeUs>(cycle_ms ? cycle_ms : 1000) * 1000;
}

// The stator frequency at which the frequency-driven losses (stray, iron on the nominal V/f
// profile, harmonic) are largest at the given current: the conservative stand-in for a lost
// frequency signal. A scan over 0..3 fnom, once at start-up.
template <class T>
T worst_frequency(const MotorConstants<T>& m, T current_a) {
  T best_f = m.rated_frequency_hz, best_p = T(-1);
  for (int k = 0; k <= 96; ++k) {
    Inputs<T> in;
    in.current_a = current_a;
    in.frequency_hz = T(3) * m.rated_frequency_hz * T(k) / T(96);
    const OperatingLosses<T> l = operating_losses(m, in);
    const T p = l.stray_w + l.iron_w + l.harmonic_w;
    if (p > best_p) {
      best_p = p;
      best_f = in.frequency_hz;
    }
  }
  return best_f;
}

}  // namespace internal

// The documented defaults. Ranges follow the nameplate; timeouts are 3 cycle times of the input's
// message (from the bus map and its DBC); grace periods are what the trainer's loader bridges (lptn/grace_periods.hpp;
// the sensors' readings are fused as they come, none held). Conservative values, each one that can
// only raise the estimate:
//   speed       0 rpm: no speed-driven cooling (effects); the rotor loss is taken from the
//               currents instead of the slip power (windage, if enabled, is then left out)
//   current     2 x rated: the converter's current limit (set your converter's)
//   frequency   the frequency of the largest frequency-driven losses (internal::worst_frequency)
//   airflow     0: natural convection only (the model's floor)
//   ambient     45 C: a hot day's cooling air (set the vehicle's design ambient)
//   torque      not used after its grace: rotor loss from the currents (the nameplate route)
//   voltage     not used after its grace: flux from the nominal V/f profile
template <class T>
EstimatorConfig<T> default_config(const MotorConstants<T>& m, EffectSet effects, const ParamVector<T>& params,
                                  const BusDecoder& bus = lptn::bus::decoder()) {
  EstimatorConfig<T> c;
  c.motor = m;
  c.effects = effects;
  c.bus = bus;
  c.params = params;
  constexpr T kPi = T(3.14159265358979);
  const T rated_torque = m.rated_power_w / (T(2) * kPi * m.base_speed_rpm() / T(60));
  const T current_limit = T(2) * m.rated_current_a;
  auto set = [&](Input i, T lo, T hi, T grace_s, T conservative) {
    c.inputs[index_of(i)] = InputLimits<T>{lo, hi, internal::timeout_us(bus, i),
                                           static_cast<TimeUs>(grace_s * T(kUsPerS)), conservative};
  };
  set(Input::speed, -T(3) * m.base_speed_rpm(), T(3) * m.base_speed_rpm(), T(grace::kElectricalS), T(0));
  set(Input::current, T(0), T(4) * m.rated_current_a, T(grace::kElectricalS), current_limit);
  set(Input::frequency, -T(3.2) * m.rated_frequency_hz, T(3.2) * m.rated_frequency_hz, T(grace::kElectricalS),
      internal::worst_frequency(m, current_limit));
  set(Input::airflow, T(0), T(5) * m.nominal_airflow_m3s, T(grace::kAirflowS), T(0));
  set(Input::ambient, T(-50), T(60), T(grace::kAmbientS), T(45));
  set(Input::torque, -T(4) * rated_torque, T(4) * rated_torque, T(grace::kElectricalS), T(0));
  set(Input::voltage, T(0), T(1.3) * m.rated_voltage_v, T(grace::kElectricalS), T(0));
  set(Input::stator_sensor, T(-50), T(250), T(0), T(0));
  set(Input::rotor_sensor, T(-50), T(300), T(0), T(0));
  return c;
}

// What a calibration says of its own uncertainty, into the observer: each parameter's spread in ln
// terms (parameter_ln_std, parameter_uncertainty.hpp, on the header's kParamStdError and flags, or on
// calibration.json's by the replay: the same function), and the process noise from the model's
// error on the calibration's test cycles beyond the stator sensor's noise. Both the firmware
// (exported_calibration.hpp) and `lptn replay` (tools/replay/calibrated_estimator.cpp) call this.
//
// The process noise: a random walk of q per sqrt(s) on a node that relaxes to the others with its
// own time constant tau = C / (sum of its conductances) stands at a spread of q sqrt(tau / 2).
// Setting that spread to the model's own error e_m (the test RMSE with the sensor's noise taken
// out: e_m^2 = rmse^2 - r^2) gives q = e_m sqrt(2 / tau) per node. The parameters' share of the
// error is then counted twice (it is in the test RMSE and in the consider states): conservative.
// A model that fits to the sensor's noise (e_m = 0) keeps kMinProcessNoiseShare of its default
// walk: what a float step and the inputs' quantization add, not a model error.
inline constexpr double kMinProcessNoiseShare = 0.0;
template <class T>
void apply_calibration_uncertainty(EstimatorConfig<T>& c, const double (&ln_std)[kNumParams], bool has_test_rmse,
                                   double test_rmse_stator_k) {
  using std::sqrt;
  for (int j = 0; j < kNumParams; ++j) c.observer.param_ln_std[j] = T(ln_std[j]);
  // The cooling factor is this motor's departure from the calibration. A calibration of this very
  // motor holds its conductances to air with their standard errors (the consider states above), so
  // the factor starts at no further spread and walks from there while readings are fused; whether
  // the calibration still holds at all is `lptn check`'s question, not a spread to guess. A type's
  // pooled calibration flashed into many motors (fleet.json) starts at the type's scatter instead
  // (ObserverSettings' default; `lptn replay --fleet` restores it).
  c.observer.cooling_initial_std = T(0);
  if (!has_test_rmse) return;  // no test cycles: no evidence of the model's error, the defaults stand
  const double r = static_cast<double>(c.observer.sensor_noise_k);
  const double excess = test_rmse_stator_k * test_rmse_stator_k - r * r;
  const double model_error_k = excess > 0.0 ? sqrt(excess) : 0.0;
  // The calibration started every cycle as the observer starts (unseen nodes at the stator's
  // reading, a soaked motor) and fitted its test cycles to within model_error_k beyond the sensor's
  // noise, start included: so far can a start put a node no sensor sees.
  c.observer.initial_std_soaked_k = T(sqrt(r * r + model_error_k * model_error_k));
  // Each node's own time constant at nominal airflow, standstill, 20 C air.
  const Model<T> model(c.motor, c.effects);
  Inputs<T> in{};
  in.airflow_m3s = c.motor.nominal_airflow_m3s;
  in.ambient_c = T(20);
  HeatBalance<T> sys;
  model.assemble(in, c.params.data(), sys);
  auto walk = [&](int i, T fallback) {
    const double rate = -static_cast<double>(sys.a[i][i]);  // 1 / tau
    if (!(rate > 0.0)) return fallback;
    const double q = model_error_k * sqrt(2.0 * rate);
    const double floor_q = kMinProcessNoiseShare * static_cast<double>(fallback);
    return T(q > floor_q ? q : floor_q);
  };
  for (int i = 0; i < kNumNodes; ++i)
    c.observer.process_noise_k_per_sqrt_s[i] = walk(i, c.observer.process_noise_k_per_sqrt_s[i]);
  c.observer.process_noise_extra_k_per_sqrt_s =
      walk(kStatorWinding, c.observer.process_noise_extra_k_per_sqrt_s);
}

}  // namespace lptn::fw
