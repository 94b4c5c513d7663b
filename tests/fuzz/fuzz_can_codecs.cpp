// Fuzz target: the codecs generated from can/codecs/lptn.dbc (lptn/can/lptn_frames.hpp) on any
// payload. Input: up to 8 payload bytes (fewer: a short frame), then, if present, 8 more read as
// a double to encode.
//
// Every message unpacks the payload, and each of its signals is checked against the DBC's
// definition (its kSignals row) through a reference that reads the frame bit by bit: the raw value,
// the decode, the range check, encode(decode(raw)), and that pack(unpack(x)) gives back exactly
// the signals' bits of x and zeros elsewhere.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <tuple>

#include "fuzz_check.hpp"
#include "lptn/can/lptn_frames.hpp"

namespace {

using namespace lptn::can;

constexpr std::size_t kMaxPayload = 8;

// One signal of a generated message: its raw member and its three static functions.
template <class Msg, class Raw>
struct Signal {
  Raw Msg::*member;
  double (*decode)(Raw) noexcept;
  Raw (*encode)(double) noexcept;
  bool (*is_in_range)(Raw) noexcept;
};

#define LPTN_SIGNAL(Msg, name)                                                                      \
  Signal<Msg, decltype(Msg::name)> {                                                                \
    &Msg::name, &Msg::name##_decode, &Msg::name##_encode, &Msg::name##_is_in_range                  \
  }

// Frame bit b is bit b % 8 of byte b / 8. A signal's bits from its least significant up: Intel
// (@1) counts up from the start bit; Motorola (@0) starts at the MSB and walks the sawtooth
// (down within a byte, then to bit 7 of the next byte), so its LSB comes last.
int frame_bit(const SignalInfo& s, int k) {
  if (!s.big_endian) return s.start + k;
  int b = s.start;
  for (int i = 0; i < s.length - 1 - k; ++i) b = b % 8 == 0 ? b + 15 : b - 1;
  return b;
}

std::uint64_t reference_raw(const std::uint8_t* frame, const SignalInfo& s) {
  std::uint64_t raw = 0;
  for (int k = 0; k < s.length; ++k) {
    const int b = frame_bit(s, k);
    raw |= static_cast<std::uint64_t>((frame[b / 8] >> (b % 8)) & 1u) << k;
  }
  return raw;
}

// As the member holds it: sign-extended for signed signals (two's complement, modulo 2^64).
std::int64_t reference_value(const std::uint8_t* frame, const SignalInfo& s) {
  std::uint64_t raw = reference_raw(frame, s);
  if (s.is_signed && s.length < 64 && (raw >> (s.length - 1) & 1u) != 0) raw |= ~std::uint64_t{0} << s.length;
  return static_cast<std::int64_t>(raw);
}

void mark_bits(const SignalInfo& s, std::uint8_t* mask) {
  for (int k = 0; k < s.length; ++k) {
    const int b = frame_bit(s, k);
    mask[b / 8] = static_cast<std::uint8_t>(mask[b / 8] | 1u << (b % 8));
  }
}

// The raw values a signal's bits can hold: the limits encode saturates to.
template <class Raw>
void raw_limits(const SignalInfo& s, Raw& low, Raw& high) {
  if (s.is_signed) {
    low = static_cast<Raw>(-(std::int64_t{1} << (s.length - 1)));
    high = static_cast<Raw>((std::int64_t{1} << (s.length - 1)) - 1);
  } else {
    low = 0;
    high = static_cast<Raw>(s.length == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << s.length) - 1);
  }
}

template <class Msg, class Raw>
void check_signal(const Msg& m, const Signal<Msg, Raw>& sig, const SignalInfo& info, const std::uint8_t* frame,
                  bool have_value, double value) {
  const Raw raw = m.*sig.member;
  LPTN_FUZZ_CHECK(static_cast<std::int64_t>(raw) == reference_value(frame, info), info.name);

  // decode is raw * factor + offset (the generator may fold the operations differently: tolerance).
  const double physical = sig.decode(raw);
  const double expected = static_cast<double>(raw) * info.factor + info.offset;
  LPTN_FUZZ_CHECK(std::isfinite(physical), info.name);
  LPTN_FUZZ_CHECK(std::fabs(physical - expected) <= 1e-9 * (1.0 + std::fabs(expected)), info.name);

  // is_in_range is the DBC's [min|max] on the physical value; the generator decides it exactly in
  // raw units, so only values clear of the bounds by more than rounding are held to it.
  if (!(info.min == 0 && info.max == 0)) {
    const double slack = 1e-6 * std::fabs(info.factor);
    if (physical > info.min + slack && physical < info.max - slack) LPTN_FUZZ_CHECK(sig.is_in_range(raw), info.name);
    if (physical < info.min - slack || physical > info.max + slack) LPTN_FUZZ_CHECK(!sig.is_in_range(raw), info.name);
  } else {
    LPTN_FUZZ_CHECK(sig.is_in_range(raw), info.name);
  }

  // A value on the wire encodes back to itself: its decode is within rounding of a whole step.
  // Holds while the raw value and offset/factor fit a double's 53 bits with room to spare.
  if (info.length <= 32 && std::fabs(info.offset / info.factor) < 0x1p40)
    LPTN_FUZZ_CHECK(sig.encode(physical) == raw, info.name);

  if (!have_value) return;
  Raw low{}, high{};
  raw_limits(info, low, high);
  const Raw encoded = sig.encode(value);
  if (std::isnan(value)) {
    LPTN_FUZZ_CHECK(encoded == 0, info.name);
    return;
  }
  const double a = sig.decode(low), b = sig.decode(high);
  const double lowest = std::fmin(a, b), highest = std::fmax(a, b);
  if (value > highest) {
    LPTN_FUZZ_CHECK(sig.decode(encoded) == highest, info.name);  // saturated
  } else if (value < lowest) {
    LPTN_FUZZ_CHECK(sig.decode(encoded) == lowest, info.name);
  } else {  // rounded to the nearest step
    const double step = std::fabs(info.factor);
    LPTN_FUZZ_CHECK(std::fabs(sig.decode(encoded) - value) <= 0.5 * step * (1 + 1e-9) + 1e-12 * std::fabs(value),
                    info.name);
  }
}

template <class Msg, class... Raw>
void check_message(const std::uint8_t* payload, std::size_t size, bool have_value, double value,
                   const std::tuple<Signal<Msg, Raw>...>& signals) {
  static_assert(sizeof...(Raw) == Msg::kNumSignals, "list every signal of the message, in DBC order");
  static_assert(Msg::kLength >= 1 && Msg::kLength <= kMaxPayload, "classic CAN frames with data only");

  Msg m;
  if (!m.unpack(payload, size)) {
    // Too short: documented to change nothing, so every member is still its default of zero.
    LPTN_FUZZ_CHECK(size < Msg::kLength, Msg::kName);
    std::apply([&](const auto&... sig) { LPTN_FUZZ_CHECK(((m.*sig.member == 0) && ...), Msg::kName); }, signals);
    return;
  }
  LPTN_FUZZ_CHECK(size >= Msg::kLength, Msg::kName);

  std::uint8_t frame[kMaxPayload]{};  // the message's bytes; unpack reads only these
  std::memcpy(frame, payload, Msg::kLength);
  std::size_t i = 0;
  std::apply([&](const auto&... sig) { (check_signal(m, sig, Msg::kSignals[i++], frame, have_value, value), ...); },
             signals);

  std::uint8_t mask[kMaxPayload]{};
  for (const SignalInfo& s : Msg::kSignals) mark_bits(s, mask);
  std::uint8_t packed[kMaxPayload];
  std::memset(packed, 0xA5, sizeof packed);
  LPTN_FUZZ_CHECK(!m.pack(packed, Msg::kLength - 1u), "pack into too small a buffer");
  for (std::uint8_t byte : packed) LPTN_FUZZ_CHECK(byte == 0xA5, "pack wrote into too small a buffer");
  LPTN_FUZZ_CHECK(m.pack(packed, sizeof packed), Msg::kName);
  for (std::size_t k = 0; k < Msg::kLength; ++k) {
    LPTN_FUZZ_CHECK((packed[k] & mask[k]) == (frame[k] & mask[k]), "pack(unpack(x)) changed a signal's bits");
    LPTN_FUZZ_CHECK((packed[k] & ~mask[k]) == 0, "pack left a bit outside every signal set");
  }
}

template <class Msg>
constexpr bool listed(std::uint32_t id) {
  return Msg::kId == id;
}

// The messages checked below are all that LPTN receives or sends: a new one breaks this build.
constexpr bool covers_every_message() {
  auto known = [](std::uint32_t id) {
    return listed<TcElectrical>(id) || listed<TcTorque>(id) || listed<TcVoltage>(id) || listed<TcCooling>(id) ||
           listed<TcStatorTemp>(id) || listed<BenchRotorTemp>(id) || listed<LptnTemperatures>(id) ||
           listed<LptnTemperatureStd>(id) || listed<LptnMargin>(id) || listed<LptnStatus>(id) ||
           listed<LptnInnovation>(id) || listed<LptnCooling>(id);
  };
  for (std::uint32_t id : kReceivedIds)
    if (!known(id)) return false;
  for (std::uint32_t id : kTransmittedIds)
    if (!known(id)) return false;
  return std::size(kReceivedIds) + std::size(kTransmittedIds) == 12;
}
static_assert(covers_every_message(), "a message was added to the DBC: add it to fuzz_can_codecs.cpp");

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::size_t payload_size = size < kMaxPayload ? size : kMaxPayload;
  std::uint8_t payload[kMaxPayload]{};
  std::memcpy(payload, data, payload_size);
  double value = 0;
  const bool have_value = size >= kMaxPayload + sizeof value;
  if (have_value) std::memcpy(&value, data + kMaxPayload, sizeof value);

  auto check = [&](const auto& signals) {
    check_message(payload, payload_size, have_value, value, signals);
  };
  check(std::tuple{LPTN_SIGNAL(TcElectrical, motor_speed), LPTN_SIGNAL(TcElectrical, stator_frequency),
                   LPTN_SIGNAL(TcElectrical, stator_current), LPTN_SIGNAL(TcElectrical, pulses_enabled),
                   LPTN_SIGNAL(TcElectrical, alive_counter)});
  check(std::tuple{LPTN_SIGNAL(TcTorque, motor_torque), LPTN_SIGNAL(TcTorque, alive_counter)});
  check(std::tuple{LPTN_SIGNAL(TcVoltage, stator_voltage), LPTN_SIGNAL(TcVoltage, alive_counter)});
  check(std::tuple{LPTN_SIGNAL(TcCooling, cooling_airflow), LPTN_SIGNAL(TcCooling, ambient_temp),
                   LPTN_SIGNAL(TcCooling, alive_counter)});
  check(std::tuple{LPTN_SIGNAL(TcStatorTemp, stator_winding_temp), LPTN_SIGNAL(TcStatorTemp, alive_counter)});
  check(std::tuple{LPTN_SIGNAL(BenchRotorTemp, rotor_temp), LPTN_SIGNAL(BenchRotorTemp, alive_counter)});
  check(std::tuple{LPTN_SIGNAL(LptnTemperatures, crc), LPTN_SIGNAL(LptnTemperatures, counter), LPTN_SIGNAL(LptnTemperatures, stator_winding_temp), LPTN_SIGNAL(LptnTemperatures, stator_core_temp),
                   LPTN_SIGNAL(LptnTemperatures, rotor_winding_temp), LPTN_SIGNAL(LptnTemperatures, rotor_core_temp)});
  check(std::tuple{LPTN_SIGNAL(LptnTemperatureStd, crc), LPTN_SIGNAL(LptnTemperatureStd, counter), LPTN_SIGNAL(LptnTemperatureStd, stator_winding_std), LPTN_SIGNAL(LptnTemperatureStd, stator_core_std),
                   LPTN_SIGNAL(LptnTemperatureStd, rotor_winding_std), LPTN_SIGNAL(LptnTemperatureStd, rotor_core_std)});
  check(std::tuple{LPTN_SIGNAL(LptnMargin, crc), LPTN_SIGNAL(LptnMargin, counter), LPTN_SIGNAL(LptnMargin, limiting_node), LPTN_SIGNAL(LptnMargin, margin),
                   LPTN_SIGNAL(LptnMargin, margin_conservative), LPTN_SIGNAL(LptnMargin, limiting_node_limit)});
  check(std::tuple{LPTN_SIGNAL(LptnStatus, crc), LPTN_SIGNAL(LptnStatus, status_counter), LPTN_SIGNAL(LptnStatus, stale_inputs), LPTN_SIGNAL(LptnStatus, implausible_inputs),
                   LPTN_SIGNAL(LptnStatus, substituted_inputs), LPTN_SIGNAL(LptnStatus, stator_sensor_state),
                   LPTN_SIGNAL(LptnStatus, mode), LPTN_SIGNAL(LptnStatus, torque_route_active),
                   LPTN_SIGNAL(LptnStatus, voltage_route_active), LPTN_SIGNAL(LptnStatus, actor_scheduling),
                   LPTN_SIGNAL(LptnStatus, rejected_readings), LPTN_SIGNAL(LptnStatus, bus_events)});
  check(std::tuple{LPTN_SIGNAL(LptnInnovation, crc), LPTN_SIGNAL(LptnInnovation, counter), LPTN_SIGNAL(LptnInnovation, innovation), LPTN_SIGNAL(LptnInnovation, innovation_std),
                   LPTN_SIGNAL(LptnInnovation, test_ratio), LPTN_SIGNAL(LptnInnovation, observer_ticks)});
  check(std::tuple{LPTN_SIGNAL(LptnCooling, crc), LPTN_SIGNAL(LptnCooling, counter), LPTN_SIGNAL(LptnCooling, cooling_factor),
                   LPTN_SIGNAL(LptnCooling, cooling_factor_std), LPTN_SIGNAL(LptnCooling, cooling_state),
                   LPTN_SIGNAL(LptnCooling, cooling_alarm)});
  return 0;
}
