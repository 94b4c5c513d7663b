#pragma once
// The measured channels of a fleet dump and the limits the loader applies to each.

#include <array>
#include <cstddef>
#include <optional>
#include <string_view>

#include "lptn/grace_periods.hpp"

namespace lptn::data {

enum class Channel : int {
  speed_rpm,
  torque_nm,
  current_a,
  frequency_hz,
  voltage_v,
  airflow_m3s,
  ambient_c,
  stator_winding_c,
  rotor_c,
};
inline constexpr int kNumChannels = 9;

// A gap in a channel the simulation is driven by cannot be filled in, so the cycle is cut there;
// a gap in a channel that is only compared against (or only informative) just leaves a hole.
enum class GapPolicy { split, mask };

struct ChannelInfo {
  std::string_view name;  // CSV column name
  std::string_view unit;
  bool required;
  double min, max;  // physically impossible outside: a value there is a logging fault, not data
  double max_gap_s;  // default longest span linear interpolation may bridge (lptn/grace_periods.hpp)
  GapPolicy on_long_gap;
};

inline constexpr std::string_view kTimeColumn = "time_s";

inline constexpr std::array<ChannelInfo, kNumChannels> kChannelTable{{
    {"speed_rpm", "1/min", true, -20000.0, 20000.0, grace::kElectricalS, GapPolicy::split},
    {"torque_nm", "N·m", false, -1e5, 1e5, grace::kElectricalS, GapPolicy::mask},
    {"current_a", "A", true, 0.0, 20000.0, grace::kElectricalS, GapPolicy::split},
    {"frequency_hz", "Hz", true, -1000.0, 1000.0, grace::kElectricalS, GapPolicy::split},
    {"voltage_v", "V", false, 0.0, 20000.0, grace::kElectricalS, GapPolicy::mask},
    {"airflow_m3s", "m³/s", true, 0.0, 100.0, grace::kAirflowS, GapPolicy::split},
    {"ambient_c", "°C", true, -60.0, 70.0, grace::kAmbientS, GapPolicy::split},
    {"stator_winding_c", "°C", true, -60.0, 400.0, grace::kTemperatureSensorS, GapPolicy::mask},
    {"rotor_c", "°C", false, -60.0, 400.0, grace::kTemperatureSensorS, GapPolicy::mask},
}};

inline constexpr std::array<Channel, kNumChannels> kAllChannels{
    Channel::speed_rpm, Channel::torque_nm,   Channel::current_a,
    Channel::frequency_hz, Channel::voltage_v, Channel::airflow_m3s,
    Channel::ambient_c, Channel::stator_winding_c, Channel::rotor_c,
};

constexpr std::size_t index_of(Channel c) { return static_cast<std::size_t>(c); }
constexpr const ChannelInfo& channel_info(Channel c) { return kChannelTable[index_of(c)]; }
constexpr std::string_view channel_name(Channel c) { return channel_info(c).name; }

constexpr std::optional<Channel> channel_from_name(std::string_view name) {
  for (Channel c : kAllChannels) {
    if (channel_name(c) == name) return c;
  }
  return std::nullopt;
}

constexpr std::array<double, kNumChannels> default_max_gaps() {
  std::array<double, kNumChannels> gaps{};
  for (std::size_t i = 0; i < gaps.size(); ++i) gaps[i] = kChannelTable[i].max_gap_s;
  return gaps;
}

// The table is indexed by the enum; keep the two in the same order.
static_assert([] {
  for (std::size_t i = 0; i < kAllChannels.size(); ++i) {
    if (index_of(kAllChannels[i]) != i) return false;
  }
  return channel_from_name("speed_rpm") == Channel::speed_rpm &&
         channel_from_name("rotor_c") == Channel::rotor_c &&
         channel_from_name("stator_winding_c") == Channel::stator_winding_c;
}());

}  // namespace lptn::data
