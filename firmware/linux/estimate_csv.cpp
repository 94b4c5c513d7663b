#include "estimate_csv.hpp"

#include <cmath>

namespace lptn::fw {
namespace {

// Nine significant digits: a float (the loader stores inputs as float) survives the round trip.
void put(std::FILE* out, double v) {
  if (std::isnan(v)) {
    std::fputc(',', out);
  } else {
    std::fprintf(out, ",%.9g", v);
  }
}

}  // namespace

void write_estimate_header(std::FILE* out) {
  std::fputs(
      "time_s,speed_rpm,torque_nm,current_a,frequency_hz,voltage_v,airflow_m3s,ambient_c,stator_winding_c,rotor_c,"
      "est_stator_winding_c,est_stator_core_c,est_rotor_winding_c,est_rotor_core_c,"
      "std_stator_winding_k,std_stator_core_k,std_rotor_winding_k,std_rotor_core_k,"
      "limiting_node,margin_k,margin_conservative_k,mode,stator_sensor,innovation_k,innovation_std_k,test_ratio,"
      "rejected_readings,stale_inputs,implausible_inputs,substituted_inputs,torque_route,voltage_route,actor,"
      "bus_events,cooling_factor,cooling_factor_std,cooling_state,cooling_alarm\n",
      out);
}

void write_estimate_row(std::FILE* out, const EstimatorOutput<double>& o, TimeUs t0_us) {
  const TimeUs t = o.time_us - t0_us;
  std::fprintf(out, "%lld.%06lld", static_cast<long long>(t / kUsPerS), static_cast<long long>(t % kUsPerS));
  const Inputs<double>& in = o.inputs;
  put(out, in.speed_rpm);
  put(out, in.has_torque ? in.torque_nm : NAN);
  put(out, in.current_a);
  put(out, in.frequency_hz);
  put(out, in.has_voltage ? in.voltage_v : NAN);
  put(out, in.airflow_m3s);
  put(out, in.ambient_c);
  put(out, o.stator_reading_c);
  put(out, o.rotor_reading_c);
  for (double v : o.node_c) std::fprintf(out, ",%.6f", v);
  for (double v : o.node_std_k) std::fprintf(out, ",%.6f", v);
  std::fprintf(out, ",%d,%.6f,%.6f,%u,%u,%.6f,%.6f,%.6f,%u,%u,%u,%u,%d,%d,%d,%u,%.6f,%.6f,%u,%d\n", o.limiting_node, o.margin_k,
               o.margin_conservative_k, static_cast<unsigned>(o.mode), static_cast<unsigned>(o.sensor),
               o.fusion.innovation_k, o.fusion.innovation_std_k, o.fusion.test_ratio,
               static_cast<unsigned>(o.rejected_readings), static_cast<unsigned>(o.stale),
               static_cast<unsigned>(o.implausible), static_cast<unsigned>(o.substituted), o.torque_route ? 1 : 0,
               o.voltage_route ? 1 : 0, o.actor_scheduling ? 1 : 0, static_cast<unsigned>(o.bus_events),
               o.cooling_factor, o.cooling_factor_std, static_cast<unsigned>(o.cooling_state), o.cooling_alarm ? 1 : 0);
}

}  // namespace lptn::fw
