// The estimator's output as the DBC's frames (LPTN_Temperatures, LPTN_TemperatureStd, LPTN_Margin,
// LPTN_Status, LPTN_Innovation, LPTN_Cooling), encoded by the generated codecs: values beyond a signal's range
// saturate there rather than wrap. Every frame is end-to-end protected (e2e.hpp): its counter
// counts the frames of its message sent, and its CRC covers its data id (the DBC's message id)
// and every other byte. The CAN ids are the bus map's (bus.toml [outputs], compiled in as
// lptn::bus::kOutputIds; lptn.dbc's by default); the data id stays the DBC's, whatever the CAN id.
#pragma once

#include <cmath>
#include <iterator>
#include <string_view>

#include "lptn/bus/bus_glue.hpp"
#include "lptn/can/lptn_frames.hpp"
#include "lptn/firmware/bus_decoder.hpp"
#include "lptn/firmware/output_ids.hpp"
#include "lptn/firmware/can_frame.hpp"
#include "lptn/firmware/e2e.hpp"
#include "lptn/firmware/estimator.hpp"

namespace lptn::fw {

namespace internal {

// The byte a message's Crc signal fills (the DBC's layout; a DBC without one fails the build).
template <class Msg>
constexpr int crc_byte() {
  for (const auto& s : Msg::kSignals)
    if (std::string_view(s.name) == "Crc") return s.start / 8;
  return -1;
}

// The message as a frame with its E2E counter and, computed over the rest, its CRC.
template <class Msg>
CanFrame protect(const Msg& message, std::uint8_t counter) {
  constexpr int kCrcByte = crc_byte<Msg>();
  Msg m = message;
  static_assert(kCrcByte >= 0, "every LPTN_* message carries a Crc signal (can/codecs/lptn.dbc)");
  if constexpr (requires { m.counter; }) {
    m.counter = static_cast<std::uint8_t>(counter & 0xF);
  } else {
    m.status_counter = static_cast<std::uint8_t>(counter & 0xF);
  }
  m.crc = 0;
  const CanFrame unprotected = to_frame(m);
  m.crc = e2e::frame_crc(static_cast<std::uint16_t>(Msg::kId), unprotected.data, unprotected.len, kCrcByte);
  return to_frame(m);
}

constexpr bool same_output_names() {
  static_assert(std::size(lptn::bus::kOutputNames) == static_cast<std::size_t>(kMaxOutputFrames));
  for (int i = 0; i < kMaxOutputFrames; ++i)
    if (std::string_view(lptn::bus::kOutputNames[i]) != kOutputFrames[i].name) return false;
  return true;
}
static_assert(same_output_names(), "can/bus/bus_vocabulary.hpp's kOutputFrameNames (the glue's kOutputNames) and kOutputFrames list the frames alike");

}  // namespace internal


// Fills `frames` and returns how many: only the status frame until the estimator is initialized.
// `ids`: the CAN id of each frame, in kOutputFrames' order (the compiled-in bus map's by default).
template <class T>
int pack_outputs(const EstimatorOutput<T>& o, CanFrame (&frames)[kMaxOutputFrames],
                 const OutputId (&ids)[kMaxOutputFrames] = lptn::bus::kOutputIds) {
  using namespace can;
  LptnStatus status;
  status.stale_inputs = o.stale;
  status.implausible_inputs = o.implausible;
  status.substituted_inputs = o.substituted;
  status.stator_sensor_state = static_cast<std::uint8_t>(o.sensor);
  status.mode = static_cast<std::uint8_t>(o.mode);
  status.torque_route_active = o.torque_route ? 1 : 0;
  status.voltage_route_active = o.voltage_route ? 1 : 0;
  status.actor_scheduling = o.actor_scheduling ? 1 : 0;
  status.rejected_readings = static_cast<std::uint8_t>(o.rejected_readings > 255 ? 255 : o.rejected_readings);
  status.bus_events = static_cast<std::uint8_t>(o.bus_events & 0x7F);
  const auto on = [&ids](CanFrame f, int index) {
    f.id = ids[index].id;
    f.extended = ids[index].extended;
    return f;
  };
  if (!o.initialized) {
    frames[0] = on(internal::protect(status, o.status_counter), 3);
    return 1;
  }
  const double c[4] = {double(o.node_c[0]), double(o.node_c[1]), double(o.node_c[2]), double(o.node_c[3])};
  const double sd[4] = {double(o.node_std_k[0]), double(o.node_std_k[1]), double(o.node_std_k[2]),
                        double(o.node_std_k[3])};
  LptnTemperatures temps;
  temps.stator_winding_temp = LptnTemperatures::stator_winding_temp_encode(c[0]);
  temps.stator_core_temp = LptnTemperatures::stator_core_temp_encode(c[1]);
  temps.rotor_winding_temp = LptnTemperatures::rotor_winding_temp_encode(c[2]);
  temps.rotor_core_temp = LptnTemperatures::rotor_core_temp_encode(c[3]);
  LptnTemperatureStd stds;
  stds.stator_winding_std = LptnTemperatureStd::stator_winding_std_encode(sd[0]);
  stds.stator_core_std = LptnTemperatureStd::stator_core_std_encode(sd[1]);
  stds.rotor_winding_std = LptnTemperatureStd::rotor_winding_std_encode(sd[2]);
  stds.rotor_core_std = LptnTemperatureStd::rotor_core_std_encode(sd[3]);
  LptnMargin margin;
  margin.limiting_node = static_cast<std::uint8_t>(o.limiting_node);
  margin.margin = LptnMargin::margin_encode(double(o.margin_k));
  margin.margin_conservative = LptnMargin::margin_conservative_encode(double(o.margin_conservative_k));
  margin.limiting_node_limit = LptnMargin::limiting_node_limit_encode(double(o.limit_c));
  LptnInnovation innovation;
  innovation.innovation = LptnInnovation::innovation_encode(double(o.fusion.innovation_k));
  innovation.innovation_std = LptnInnovation::innovation_std_encode(double(o.fusion.innovation_std_k));
  innovation.test_ratio = LptnInnovation::test_ratio_encode(double(o.fusion.test_ratio));
  innovation.observer_ticks = static_cast<std::uint16_t>(o.ticks & 0xFFFF);
  LptnCooling cooling;
  cooling.cooling_factor = LptnCooling::cooling_factor_encode(double(o.cooling_factor));
  cooling.cooling_factor_std = LptnCooling::cooling_factor_std_encode(double(o.cooling_factor_std));
  cooling.cooling_state = static_cast<std::uint8_t>(o.cooling_state);
  cooling.cooling_alarm = o.cooling_alarm ? 1 : 0;
  // The other frames go out once a tick from the start on, as the ticks count.
  const auto counter = static_cast<std::uint8_t>(o.ticks & 0xF);
  frames[0] = on(internal::protect(temps, counter), 0);
  frames[1] = on(internal::protect(stds, counter), 1);
  frames[2] = on(internal::protect(margin, counter), 2);
  frames[3] = on(internal::protect(status, o.status_counter), 3);
  frames[4] = on(internal::protect(innovation, counter), 4);
  frames[5] = on(internal::protect(cooling, counter), 5);
  return 6;
}

}  // namespace lptn::fw
