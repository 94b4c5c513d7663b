// The on-board estimator: CAN frames in, conditioned inputs, the observer ticking at a fixed step,
// estimates and health out. What the Linux daemon, the replay and a bare-metal port all run.
//
//   receive(frame, t)  decode through the bus map's decoder (config.bus), check length and
//                      alive counter, hand the values to signal conditioning
//   tick(t)            once per step: predict from the inputs sampled at the previous tick, fuse
//                      a new stator reading, sample the inputs for the next step, publish
//
// The state at tick k is the model's after k steps, each run on the inputs of the tick before,
// exactly as the trainer's run_cycle() (trainer/model/simulate.hpp) steps a cycle's grid.
// No heap, no exceptions, bounded loops; everything is held by value.
#pragma once

#include <cmath>
#include <cstdint>

#include "lptn/firmware/can_frame.hpp"
#include "lptn/firmware/e2e.hpp"
#include "lptn/firmware/estimator_config.hpp"

namespace lptn::fw {

// As the status frame's Mode (can/codecs/lptn.dbc).
enum class Mode : std::uint8_t { normal = 0, degraded = 1, conservative = 2, not_initialized = 3 };

// Bits of the status frame's BusEvents: what happened since the previous tick.
namespace bus_event {
inline constexpr std::uint8_t kUnknownId = 1u << 0;
inline constexpr std::uint8_t kWrongLength = 1u << 1;
inline constexpr std::uint8_t kErrorFrame = 1u << 2;
inline constexpr std::uint8_t kTimeBackwards = 1u << 3;
inline constexpr std::uint8_t kTimeForwards = 1u << 4;
inline constexpr std::uint8_t kOverrun = 1u << 5;
inline constexpr std::uint8_t kE2EFault = 1u << 6;  // an input frame dropped: its CRC failed, its counter repeated or jumped
}  // namespace bus_event

template <class T>
struct EstimatorOutput {
  TimeUs time_us = 0;
  bool initialized = false;
  std::uint32_t ticks = 0;  // steps since initialization
  T node_c[kNumNodes]{};
  T node_std_k[kNumNodes]{};
  int limiting_node = 0;  // the node closest to its limit
  T margin_k = T(0);      // its limit minus its estimate
  T margin_conservative_k = T(0);  // ... minus two standard deviations more
  T limit_c = T(0);
  InputMask stale = 0, implausible = 0, substituted = 0;
  SensorState sensor = SensorState::unavailable;
  Mode mode = Mode::not_initialized;
  bool torque_route = false;   // rotor loss from the slip power
  bool voltage_route = false;  // flux from V/f
  bool actor_scheduling = false;
  std::uint32_t rejected_readings = 0;
  std::uint8_t bus_events = 0;
  std::uint8_t status_counter = 0;  // 4 bits, +1 every tick
  Fusion<T> fusion{};               // the last stator reading's
  T cooling_factor = T(1);          // on the conductances to air; 1: as calibrated
  T cooling_factor_std = T(0);
  CoolingState cooling_state = CoolingState::off;
  bool cooling_alarm = false;
  Inputs<T> inputs{};               // what the next step runs on
  T stator_reading_c = T(NAN);      // the fresh readings this tick (NaN: none)
  T rotor_reading_c = T(NAN);
};

template <class T>
class Estimator {
 public:
  explicit Estimator(const EstimatorConfig<T>& config)
      : config_(config),
        observer_(config.motor, config.effects, config.observer),
        monitor_(config.sensor),
        cooling_alarm_(config.cooling_alarm) {
    for (int i = 0; i < kNumInputs; ++i) inputs_.set_limits(static_cast<Input>(i), config.inputs[i]);
    params_ = config.params;
  }

  const EstimatorConfig<T>& config() const { return config_; }
  const Observer<T>& observer() const { return observer_; }
  const EstimatorOutput<T>& output() const { return out_; }
  const InputConditioner<T>& input_conditioner() const { return inputs_; }

  void receive(const CanFrame& f, TimeUs t) {
    if (have_rx_ && t < last_rx_) events_ |= bus_event::kTimeBackwards;
    if (!have_rx_ || t > last_rx_) last_rx_ = t;
    have_rx_ = true;
    const TimeUs now = last_rx_;  // a frame from the past is taken as received now
    if (f.error) {
      events_ |= bus_event::kErrorFrame;
      return;
    }
    BusReading r;
    if (config_.bus.decode == nullptr || !config_.bus.decode(config_.bus.context, f, r)) {
      events_ |= bus_event::kUnknownId;
      return;
    }
    if (r.malformed || r.message < 0 || r.message >= kMaxBusMessages) {
      events_ |= bus_event::kWrongLength;
      return;
    }
    // E2E: the CRC first, so that a corrupted frame's counter does not move the count.
    bool dropped = r.has_crc && !r.crc_ok;
    if (!dropped && r.has_counter) {
      const e2e::CounterCheck c = counters_[r.message].step(r.counter, r.counter_modulo, r.max_delta_counter);
      dropped = c == e2e::CounterCheck::repeated || c == e2e::CounterCheck::jumped;
    }
    if (dropped) {
      events_ |= bus_event::kE2EFault;
      for (int i = 0; i < kNumInputs; ++i)
        if (r.carried & bit(static_cast<Input>(i))) inputs_.counter_fault(static_cast<Input>(i));
      return;
    }
    for (int k = 0; k < r.n; ++k) inputs_.receive(r.input[k], T(r.value[k]), now);
  }

  // The receiving driver lost frames (socket buffer overrun).
  void note_overrun() { events_ |= bus_event::kOverrun; }

  // One fixed step at time t (microseconds, the frames' clock).
  const EstimatorOutput<T>& tick(TimeUs t) {
    const TimeUs dt_us = static_cast<TimeUs>(config_.observer.dt_s * T(kUsPerS) + T(0.5));
    if (have_tick_ && t < last_tick_) events_ |= bus_event::kTimeBackwards;
    if (have_tick_ && t - last_tick_ > dt_us + dt_us / 2) events_ |= bus_event::kTimeForwards;
    last_tick_ = t;
    have_tick_ = true;

    if (!out_.initialized) {
      if (!try_initialize(t)) return publish_uninitialized(t);
    } else {
      const T before = observer_.stator_sensor_c();
      // Open loop: nothing corrects the cooling factor, so it stands as last estimated.
      observer_.predict(next_inputs_, params_.data(), cooling_state() == CoolingState::frozen);
      model_motion_ += observer_.stator_sensor_c() - before;
      fuse_stator_reading(t);
      ++out_.ticks;
    }
    sample_inputs(t);
    return publish(t);
  }

 private:
  CoolingState cooling_state() const {
    if (!observer_.estimates_cooling()) return CoolingState::off;
    return sensor_ == SensorState::fused || sensor_ == SensorState::rejected ? CoolingState::tracking
                                                                             : CoolingState::frozen;
  }

  bool required_fresh(TimeUs t) const {
    for (int i = 0; i < kNumInputs; ++i) {
      const Input in = static_cast<Input>(i);
      if ((kRequiredInputs & bit(in)) && inputs_.sample(in, t).use != InputUse::fresh) return false;
    }
    return true;
  }

  bool try_initialize(TimeUs t) {
    if (!required_fresh(t)) {
      waiting_since_valid_ = false;
      return false;
    }
    if (!waiting_since_valid_) {
      waiting_since_ = t;
      waiting_since_valid_ = true;
    }
    const InputSample<T> stator = inputs_.sample(Input::stator_sensor, t);
    const InputSample<T> rotor = inputs_.sample(Input::rotor_sensor, t);
    const bool stator_ok = stator.use == InputUse::fresh;
    const bool rotor_ok = rotor.use == InputUse::fresh;
    // A rotor telemetry (benches) is given its timeout to show up, so that the rotor nodes start
    // at its reading as the trainer starts them (trainer/model/simulate.hpp), not at the stator's.
    const bool rotor_waited = rotor_ok || t - waiting_since_ >= config_.inputs[index_of(Input::rotor_sensor)].timeout_us;
    if (stator_ok && !rotor_waited) return false;
    if (stator_ok) {
      observer_.initialize(stator.value, true, rotor.value, rotor_ok);
      last_stator_sequence_ = inputs_.sequence(Input::stator_sensor);  // the start is that reading
    } else if (t - waiting_since_ >= config_.start_without_sensor_after_us) {
      observer_.initialize(config_.start_without_sensor_c, false, rotor.value, rotor_ok);
    } else {
      return false;
    }
    out_.initialized = true;
    out_.ticks = 0;
    sensor_ = stator_ok && config_.fuse_stator_sensor ? SensorState::fused : SensorState::unavailable;
    return true;
  }

  void fuse_stator_reading(TimeUs t) {
    const InputSample<T> reading = inputs_.sample(Input::stator_sensor, t);
    const unsigned sequence = inputs_.sequence(Input::stator_sensor);
    if (reading.use != InputUse::fresh) {
      sensor_ = monitor_.failed() ? SensorState::failed_open_loop : SensorState::unavailable;
      return;
    }
    if (sequence == last_stator_sequence_) return;  // fused already: the state from then stands
    last_stator_sequence_ = sequence;
    Fusion<T> f = observer_.test(reading.value);
    const bool may_fuse = monitor_.on_reading(reading.value, model_motion_, f.test_ratio <= T(1), t);
    model_motion_ = T(0);
    if (monitor_.failed()) {
      sensor_ = SensorState::failed_open_loop;
    } else if (!config_.fuse_stator_sensor) {
      sensor_ = SensorState::unavailable;
    } else if (may_fuse) {
      observer_.fuse(f);
      sensor_ = SensorState::fused;
    } else {
      sensor_ = SensorState::rejected;
    }
    out_.fusion = f;
  }

  // The inputs the next step runs on, each as conditioning allows, and the parameters for them.
  void sample_inputs(TimeUs t) {
    substituted_ = 0;
    held_ = 0;
    auto take = [&](Input i) {
      const InputSample<T> s = inputs_.sample(i, t);
      if (s.use == InputUse::substituted) substituted_ |= bit(i);
      if (s.use == InputUse::held) held_ |= bit(i);
      return s;
    };
    const InputSample<T> speed = take(Input::speed), current = take(Input::current), frequency = take(Input::frequency);
    const InputSample<T> airflow = take(Input::airflow), ambient = take(Input::ambient);
    const InputSample<T> torque = take(Input::torque), voltage = take(Input::voltage);
    auto measured = [](const InputSample<T>& s) { return s.use == InputUse::fresh || s.use == InputUse::held; };
    Inputs<T> in;
    in.speed_rpm = speed.value;
    in.current_a = current.value;
    in.frequency_hz = frequency.value;
    in.airflow_m3s = airflow.value;
    in.ambient_c = ambient.value;
    // The slip power needs torque, speed and frequency as measured; V/f needs both its values.
    in.has_torque = measured(torque) && measured(speed) && measured(frequency);
    in.torque_nm = in.has_torque ? torque.value : T(0);
    in.has_voltage = measured(voltage) && measured(frequency);
    in.voltage_v = in.has_voltage ? voltage.value : T(0);
    next_inputs_ = in;
    schedule_parameters(in);
  }

  void schedule_parameters(const Inputs<T>& in) {
    actor_active_ = config_.use_actor && config_.actor.actor != nullptr && in.has_torque;
    if (!actor_active_) {
      params_ = config_.params;
      return;
    }
    const ActorSchedule& a = config_.actor;
    const float obs[2] = {static_cast<float>((double(in.speed_rpm) - a.obs_offset[0]) / a.obs_scale[0]),
                          static_cast<float>((double(in.torque_nm) - a.obs_offset[1]) / a.obs_scale[1])};
    float u[32];
    if (!actor_forward<256, 32>(*a.actor, obs, u)) {
      actor_active_ = false;
      params_ = config_.params;
      return;
    }
    for (int j = 0; j < a.outputs(); ++j)
      params_[a.param_index[j]] = T(from_normalized(static_cast<double>(u[j]), a.param_min[j], a.param_max[j]));
  }

  const EstimatorOutput<T>& publish_uninitialized(TimeUs t) {
    out_.time_us = t;
    out_.mode = Mode::not_initialized;
    out_.sensor = SensorState::unavailable;
    out_.stale = inputs_.stale_mask(t);
    out_.implausible = inputs_.implausible_mask();
    out_.substituted = 0;
    finish_status();
    return out_;
  }

  const EstimatorOutput<T>& publish(TimeUs t) {
    out_.time_us = t;
    T worst = T(1e30);
    for (int i = 0; i < kNumNodes; ++i) {
      out_.node_c[i] = observer_.node_c(i);
      out_.node_std_k[i] = observer_.node_std_k(i);
      const T margin = config_.node_limit_c[i] - out_.node_c[i];
      if (margin < worst) {
        worst = margin;
        out_.limiting_node = i;
      }
    }
    out_.margin_k = worst;
    out_.margin_conservative_k = worst - T(2) * out_.node_std_k[out_.limiting_node];
    out_.limit_c = config_.node_limit_c[out_.limiting_node];
    out_.stale = inputs_.stale_mask(t);
    out_.implausible = inputs_.implausible_mask();
    out_.substituted = substituted_;
    out_.sensor = sensor_;
    out_.torque_route = next_inputs_.has_torque;
    out_.voltage_route = next_inputs_.has_voltage;
    out_.actor_scheduling = actor_active_;
    out_.rejected_readings = monitor_.rejections();
    out_.cooling_state = cooling_state();
    out_.cooling_factor = observer_.cooling_factor();
    out_.cooling_factor_std = observer_.cooling_factor_std();
    out_.cooling_alarm = cooling_alarm_.update(out_.cooling_factor, out_.cooling_factor_std, out_.cooling_state);
    out_.inputs = next_inputs_;
    const InputSample<T> stator = inputs_.sample(Input::stator_sensor, t);
    const InputSample<T> rotor = inputs_.sample(Input::rotor_sensor, t);
    out_.stator_reading_c = stator.use == InputUse::fresh ? stator.value : T(NAN);
    out_.rotor_reading_c = rotor.use == InputUse::fresh ? rotor.value : T(NAN);
    const bool optional_lost = (substituted_ & (bit(Input::torque) | bit(Input::voltage))) != 0;
    if (substituted_ & kRequiredInputs) {
      out_.mode = Mode::conservative;
    } else if ((held_ & kRequiredInputs) || optional_lost || sensor_ == SensorState::failed_open_loop ||
               sensor_ == SensorState::unavailable) {
      out_.mode = Mode::degraded;
    } else {
      out_.mode = Mode::normal;
    }
    finish_status();
    return out_;
  }

  void finish_status() {
    out_.bus_events = events_;
    events_ = 0;
    out_.status_counter = static_cast<std::uint8_t>((out_.status_counter + 1) & 0xF);
  }

  EstimatorConfig<T> config_;
  Observer<T> observer_;
  SensorMonitor<T> monitor_;
  CoolingAlarm<T> cooling_alarm_;
  InputConditioner<T> inputs_;
  // Alive counters: a repeated value (frozen sender) or a jump beyond the map's MaxDeltaCounter
  // (too many frames lost, or replayed ones) marks the frame's inputs stale and its content unused.
  e2e::CounterState counters_[kMaxBusMessages];
  ParamVector<T> params_{};
  Inputs<T> next_inputs_{};
  EstimatorOutput<T> out_{};
  SensorState sensor_ = SensorState::unavailable;
  InputMask substituted_ = 0, held_ = 0;
  bool actor_active_ = false;
  T model_motion_ = T(0);  // the model's own steps since the last stator reading (sensor monitor)
  unsigned last_stator_sequence_ = 0;
  std::uint8_t events_ = 0;
  TimeUs last_rx_ = 0, last_tick_ = 0, waiting_since_ = 0;
  bool have_rx_ = false, have_tick_ = false, waiting_since_valid_ = false;
};

}  // namespace lptn::fw
