// The motor's nameplate: the ratings the model (MotorConstants), the synthetic plant (MotorSpec)
// and the fleet dump's plausibility checks all start from.
#pragma once

#include "lptn/motor_field.hpp"

namespace lptn {

// Current comes before voltage here (the motor file has them the other way round) because callers
// brace-initialize a nameplate positionally as {pole pairs, frequency, current, voltage}; swapping
// the two would still compile.
template <class R>
struct Nameplate {
  int pole_pairs = 2;
  R rated_frequency_hz = R(65);
  R rated_current_a = R(115);
  R rated_voltage_v = R(1900);
  R rated_power_w = R(310e3);

  // Synchronous speed at rated frequency.
  R base_speed_rpm() const { return R(60) * rated_frequency_hz / R(pole_pairs); }
};

// Calls f(field, n.member...) for every member of the nameplates n, in the motor file's order.
template <class F, class... N>
constexpr void for_each_nameplate_field(F&& f, N&... n) {
  f(MotorField{.section = "nameplate", .name = "pole_pairs", .shape = FieldShape::integer, .max_count = 16},
    n.pole_pairs...);
  f(MotorField{.section = "nameplate", .name = "rated_frequency_hz"}, n.rated_frequency_hz...);
  f(MotorField{.section = "nameplate", .name = "rated_voltage_v", .note = "line, RMS", .note_gap = 10},
    n.rated_voltage_v...);
  f(MotorField{.section = "nameplate", .name = "rated_current_a", .note = "phase, RMS", .note_gap = 11},
    n.rated_current_a...);
  f(MotorField{.section = "nameplate", .name = "rated_power_w"}, n.rated_power_w...);
}

}  // namespace lptn
