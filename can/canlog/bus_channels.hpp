// Which DBC signal carries which fleet-dump column: the one table both directions of
// `lptn convert` use, so that CSV -> log and log -> CSV cannot disagree. Bits, factors and ranges
// stay in the generated codecs (lptn/can/lptn_frames.hpp); this only names the pairs.
#pragma once

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string_view>
#include <tuple>

#include "lptn/can/lptn_frames.hpp"
#include "lptn/firmware/input.hpp"
#include "trainer/data/channels.hpp"

namespace lptn::canlog {

using fw::TimeUs;

// Grid step of the loader (data::LoadOptions' default), the unit of every message's cycle time.
inline constexpr TimeUs kGridStepUs = 100'000;

// One signal of an input message and the column it carries.
template <class Msg>
struct ChannelSignal {
  data::Channel channel;
  std::string_view signal;  // DBC name, for messages
  double factor, min, max;  // from the generated kSignals
  void (*encode)(Msg&, double);
  double (*decode)(const Msg&);
};

// The generated metadata of a signal by its DBC name; a typo fails the build (throw in constexpr).
template <class Msg>
constexpr const auto& signal_info(std::string_view name) {
  for (const auto& s : Msg::kSignals)
    if (std::string_view(s.name) == name) return s;
  throw std::logic_error("no such signal in the DBC");
}

template <class MemberPointer>
struct message_of;
template <class Msg, class Raw>
struct message_of<Raw Msg::*> {
  using type = Msg;
};

// Ties a raw field to its generated encoder and decoder, which round, saturate and scale.
template <auto Field, auto Encode, auto Decode, class Msg = typename message_of<decltype(Field)>::type>
constexpr ChannelSignal<Msg> bind(data::Channel channel, std::string_view signal) {
  const auto& info = signal_info<Msg>(signal);
  return {channel,
          signal,
          info.factor,
          info.min,
          info.max,
          [](Msg& m, double v) { m.*Field = Encode(v); },
          [](const Msg& m) { return static_cast<double>(Decode(m.*Field)); }};
}

template <class Msg, std::size_t N>
struct InputMessage {
  using Frame = Msg;
  // Sent this long after each grid point it carries, so that a converted log interleaves as a
  // real bus does instead of stacking every message on one time stamp.
  TimeUs phase_us;
  std::array<ChannelSignal<Msg>, N> signals;

  // Grid points between two frames: the message's cycle time in loader steps.
  static constexpr std::size_t kGridStride = Msg::kCycleTimeMs * 1000 / kGridStepUs;
  static_assert(Msg::kCycleTimeMs * 1000 % kGridStepUs == 0, "a cycle time must be a whole number of grid steps");
};

namespace bus {
using namespace can;
using data::Channel;

// The converter's inputs in phase order, which is also the order of their frames within a grid
// step. PulsesEnabled and the alive counters carry no column; the CSV -> log side fills them.
inline constexpr auto kInputMessages = std::tuple{
    InputMessage<TcElectrical, 3>{
        0,
        {bind<&TcElectrical::motor_speed, &TcElectrical::motor_speed_encode, &TcElectrical::motor_speed_decode>(
             Channel::speed_rpm, "MotorSpeed"),
         bind<&TcElectrical::stator_frequency, &TcElectrical::stator_frequency_encode,
              &TcElectrical::stator_frequency_decode>(Channel::frequency_hz, "StatorFrequency"),
         bind<&TcElectrical::stator_current, &TcElectrical::stator_current_encode,
              &TcElectrical::stator_current_decode>(Channel::current_a, "StatorCurrent")}},
    InputMessage<TcTorque, 1>{
        2'000,
        {bind<&TcTorque::motor_torque, &TcTorque::motor_torque_encode, &TcTorque::motor_torque_decode>(
            Channel::torque_nm, "MotorTorque")}},
    InputMessage<TcVoltage, 1>{
        4'000,
        {bind<&TcVoltage::stator_voltage, &TcVoltage::stator_voltage_encode, &TcVoltage::stator_voltage_decode>(
            Channel::voltage_v, "StatorVoltage")}},
    InputMessage<TcCooling, 2>{
        6'000,
        {bind<&TcCooling::cooling_airflow, &TcCooling::cooling_airflow_encode, &TcCooling::cooling_airflow_decode>(
             Channel::airflow_m3s, "CoolingAirflow"),
         bind<&TcCooling::ambient_temp, &TcCooling::ambient_temp_encode, &TcCooling::ambient_temp_decode>(
             Channel::ambient_c, "AmbientTemp")}},
    InputMessage<TcStatorTemp, 1>{
        8'000,
        {bind<&TcStatorTemp::stator_winding_temp, &TcStatorTemp::stator_winding_temp_encode,
              &TcStatorTemp::stator_winding_temp_decode>(Channel::stator_winding_c, "StatorWindingTemp")}},
    InputMessage<BenchRotorTemp, 1>{
        9'000,
        {bind<&BenchRotorTemp::rotor_temp, &BenchRotorTemp::rotor_temp_encode, &BenchRotorTemp::rotor_temp_decode>(
            Channel::rotor_c, "RotorTemp")}},
};

}  // namespace bus

// Calls f(message) for every input message, in phase order.
template <class F>
constexpr void for_each_input_message(F&& f) {
  std::apply([&](const auto&... m) { (f(m), ...); }, bus::kInputMessages);
}

// A frame of a grid point must go out before the next grid point's first frame.
static_assert([] {
  TimeUs last = -1;
  bool ascending = true;
  for_each_input_message([&](const auto& m) {
    ascending = ascending && m.phase_us > last && m.phase_us < kGridStepUs;
    last = m.phase_us;
  });
  return ascending;
}());

// Every column of the contract rides on exactly one signal, so that both directions cover it.
static_assert([] {
  std::array<int, data::kNumChannels> carried{};
  for_each_input_message([&](const auto& m) {
    for (const auto& s : m.signals) ++carried[data::index_of(s.channel)];
  });
  for (int n : carried)
    if (n != 1) return false;
  return true;
}());

// The estimator's own frames (LPTN_*): expected on a recorded bus, never a fleet-dump column.
constexpr bool is_output_frame(std::uint32_t id, bool extended) {
  for (std::uint32_t out : can::kTransmittedIds)
    if (id == out && !extended) return true;
  return false;
}

}  // namespace lptn::canlog
