// The estimator's output as the DBC's frames (LPTN_Temperatures, LPTN_TemperatureStd, LPTN_Margin,
// LPTN_Status, LPTN_Innovation), encoded by the generated codecs: values beyond a signal's range
// saturate there rather than wrap.
#pragma once

#include <cmath>

#include "lptn/can/lptn_frames.hpp"
#include "lptn/firmware/can_frame.hpp"
#include "lptn/firmware/estimator.hpp"

namespace lptn::fw {

inline constexpr int kMaxOutputFrames = 5;


// Fills `frames` and returns how many: only the status frame until the estimator is initialized.
template <class T>
int pack_outputs(const EstimatorOutput<T>& o, CanFrame (&frames)[kMaxOutputFrames]) {
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
  status.bus_events = static_cast<std::uint8_t>(o.bus_events & 0x3F);
  status.status_counter = o.status_counter;
  if (!o.initialized) {
    frames[0] = to_frame(status);
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
  frames[0] = to_frame(temps);
  frames[1] = to_frame(stds);
  frames[2] = to_frame(margin);
  frames[3] = to_frame(status);
  frames[4] = to_frame(innovation);
  return 5;
}

}  // namespace lptn::fw
