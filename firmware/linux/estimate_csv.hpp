// The estimator's output, one CSV row per tick. The first columns are the fleet-dump contract's
// (time_s and the inputs exactly as the model ran on them, the sensor readings it saw), so that a
// replay's CSV loads as a driving cycle: the trainer can simulate the very inputs the firmware
// used (the golden test does). Estimates and health follow.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>

#include "lptn/firmware/estimator.hpp"

namespace lptn::fw {

inline constexpr char kEstimateHeader[] =
    "time_s,speed_rpm,torque_nm,current_a,frequency_hz,voltage_v,airflow_m3s,ambient_c,stator_winding_c,rotor_c,"
    "est_stator_winding_c,est_stator_core_c,est_rotor_winding_c,est_rotor_core_c,"
    "std_stator_winding_k,std_stator_core_k,std_rotor_winding_k,std_rotor_core_k,"
    "limiting_node,margin_k,margin_conservative_k,mode,stator_sensor,innovation_k,innovation_std_k,test_ratio,"
    "rejected_readings,stale_inputs,implausible_inputs,substituted_inputs,torque_route,voltage_route,actor,"
    "bus_events,cooling_factor,cooling_factor_std,cooling_state,cooling_alarm\n";

// A row's bytes never exceed this (40 fields, each at most 330 characters, printf's "%.6f" of the
// largest double).
inline constexpr std::size_t kMaxEstimateRow = 40 * 332;

void write_estimate_header(std::FILE* out);
// time_s is counted from `t0_us` (the log's first frame). The numbers are printf's ("%.9g" for
// the inputs and readings, "%.6f" for the estimates), formatted without it (csv_number.hpp).
void write_estimate_row(std::FILE* out, const EstimatorOutput<double>& o, TimeUs t0_us);
// The same row, newline included, into `buf` (kMaxEstimateRow bytes); returns its length.
std::size_t format_estimate_row(char* buf, const EstimatorOutput<double>& o, TimeUs t0_us);

// format_estimate_row for one writer's rows in turn: a number that is the very double its column
// held in the row before is copied from that row's text, not formatted again. Between two readings
// that is a third of a row's numbers (airflow, ambient, the readings, the last fusion's figures, the
// cooling factor). The same bytes.
class EstimateRowFormatter {
 public:
  std::size_t format(char* buf, const EstimatorOutput<double>& o, TimeUs t0_us);

  // One column's last number and its text (length 0: none kept; texts longer than the cell are
  // formatted each time).
  struct Cell {
    std::uint64_t bits = 0;
    std::size_t length = 0;
    char text[32];
  };

 private:
  static constexpr int kNumberColumns = 24;  // the "%.9g" and "%.6f" columns of a row
  Cell cells_[kNumberColumns];
};

}  // namespace lptn::fw
