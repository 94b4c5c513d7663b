#include "estimate_csv.hpp"

#include <cassert>
#include <cmath>
#include <cstring>

#include "csv_number.hpp"

namespace lptn::fw {
namespace {

using namespace csv_number;

// Nine significant digits ("%.9g"): a float (the loader stores inputs as float) survives the round
// trip. NaN: an empty cell.
ShortText general9_or_empty_short(double v) {
  if (!std::isnan(v)) return general9_short(v);
  ShortText empty;
  empty.length = 0;
  return empty;
}
char* general9_or_empty(char* out, double v) { return std::isnan(v) ? out : put_general9(out, v); }

// A column's number: from the cell where it is the cell's double, else made (and kept). A text
// made in registers is stored from them into the row and into the cell; any other is written by
// Format and copied from the row (none of the demo's numbers is).
template <ShortText (*Short)(double), char* (*Format)(char*, double)>
char* put_cell(char* out, EstimateRowFormatter::Cell& cell, double v) {
  *out++ = ',';
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  if (cell.length != 0 && cell.bits == bits) {
    std::memcpy(out, cell.text, sizeof cell.text);  // the whole cell: a fixed copy, kMaxEstimateRow has the room
    return out + cell.length;
  }
  if (const ShortText text = Short(v); text.length >= 0) {
    static_assert(sizeof text.bytes <= sizeof cell.text);
    std::memcpy(cell.text, &text.bytes, sizeof text.bytes);
    cell.bits = bits;
    cell.length = static_cast<std::size_t>(text.length);
    return put_short(out, text);
  }
  char* end = Format(out, v);
  const std::size_t length = static_cast<std::size_t>(end - out);
  cell.length = length <= sizeof cell.text ? length : 0;
  if (cell.length != 0) {
    cell.bits = bits;
    std::memcpy(cell.text, out, sizeof cell.text);  // a fixed copy too (a call to memcpy where the length varies)
  }
  return end;
}

char* put_int_field(char* out, long long v) {
  *out++ = ',';
  return put_int(out, v);
}

// "%06lld": at least six characters, zero-padded after a minus sign; below 10^6 (a time stamp's
// microseconds) three pairs of digits from the table.
char* put_padded6(char* out, long long v) {
  if (v >= 0 && v < 1000000) {
    const std::uint64_t text = detail::six_digits_text(static_cast<std::uint64_t>(v));
    std::memcpy(out, &text, sizeof text);  // 8 bytes, the last two past the field: the row has the room
    return out + 6;
  }
  char digits[24];
  char* end = put_int(digits, v);
  const bool negative = v < 0;
  const char* first = digits + (negative ? 1 : 0);
  const long width = static_cast<long>(end - digits);
  if (negative) *out++ = '-';
  for (long pad = 6 - width; pad > 0; --pad) *out++ = '0';
  for (const char* p = first; p < end; ++p) *out++ = *p;
  return out;
}

}  // namespace

void write_estimate_header(std::FILE* out) { std::fputs(kEstimateHeader, out); }

std::size_t format_estimate_row(char* buf, const EstimatorOutput<double>& o, TimeUs t0_us) {
  EstimateRowFormatter fresh;
  return fresh.format(buf, o, t0_us);
}

std::size_t EstimateRowFormatter::format(char* buf, const EstimatorOutput<double>& o, TimeUs t0_us) {
  Cell* cell = cells_;
  auto put = [&](char* out, double v) { return put_cell<general9_or_empty_short, general9_or_empty>(out, *cell++, v); };
  auto put6 = [&](char* out, double v) { return put_cell<fixed6_short, put_fixed6>(out, *cell++, v); };
  const TimeUs t = o.time_us - t0_us;
  char* p = put_int(buf, static_cast<long long>(t / kUsPerS));
  *p++ = '.';
  p = put_padded6(p, static_cast<long long>(t % kUsPerS));
  const Inputs<double>& in = o.inputs;
  p = put(p, in.speed_rpm);
  p = put(p, in.has_torque ? in.torque_nm : NAN);
  p = put(p, in.current_a);
  p = put(p, in.frequency_hz);
  p = put(p, in.has_voltage ? in.voltage_v : NAN);
  p = put(p, in.airflow_m3s);
  p = put(p, in.ambient_c);
  p = put(p, o.stator_reading_c);
  p = put(p, o.rotor_reading_c);
  for (double v : o.node_c) p = put6(p, v);
  for (double v : o.node_std_k) p = put6(p, v);
  p = put_int_field(p, o.limiting_node);
  p = put6(p, o.margin_k);
  p = put6(p, o.margin_conservative_k);
  p = put_int_field(p, static_cast<unsigned>(o.mode));
  p = put_int_field(p, static_cast<unsigned>(o.sensor));
  p = put6(p, o.fusion.innovation_k);
  p = put6(p, o.fusion.innovation_std_k);
  p = put6(p, o.fusion.test_ratio);
  p = put_int_field(p, static_cast<unsigned>(o.rejected_readings));
  p = put_int_field(p, static_cast<unsigned>(o.stale));
  p = put_int_field(p, static_cast<unsigned>(o.implausible));
  p = put_int_field(p, static_cast<unsigned>(o.substituted));
  p = put_int_field(p, o.torque_route ? 1 : 0);
  p = put_int_field(p, o.voltage_route ? 1 : 0);
  p = put_int_field(p, o.actor_scheduling ? 1 : 0);
  p = put_int_field(p, static_cast<unsigned>(o.bus_events));
  p = put6(p, o.cooling_factor);
  p = put6(p, o.cooling_factor_std);
  p = put_int_field(p, static_cast<unsigned>(o.cooling_state));
  p = put_int_field(p, o.cooling_alarm ? 1 : 0);
  *p++ = '\n';
  assert(cell == cells_ + kNumberColumns);
  return static_cast<std::size_t>(p - buf);
}

void write_estimate_row(std::FILE* out, const EstimatorOutput<double>& o, TimeUs t0_us) {
  char row[kMaxEstimateRow];
  std::fwrite(row, 1, format_estimate_row(row, o, t0_us), out);
}

}  // namespace lptn::fw
