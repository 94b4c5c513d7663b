// A candump log through the float estimator with the compiled-in calibration, ticked by the log's
// time stamps as `lptn replay` ticks it (lptn/firmware/replay_clock.hpp), each estimate written as
// a CSV row: the bare-metal replay image (replay_main.cpp, under qemu through semihosting) and its
// host twin (tests/m7/host_float_replay.cpp, the reference its rows are held to) both run this.
// No heap: the estimator, the line and the output buffers are the caller's or static.
//
// Io: std::size_t read(char* buf, std::size_t n) (0 at the end), void write(const char* s,
// std::size_t n), and tick_started() / tick_ended() around the estimator's own work (receiving a
// frame, the ticks due before it), without parsing and writing: the image counts cycles there.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

#include "lptn/firmware/candump_line.hpp"
#include "lptn/firmware/estimator.hpp"
#include "lptn/firmware/replay_clock.hpp"

namespace lptn::fw {

struct FloatReplayResult {
  ReplayCounts counts;
  std::size_t bad_lines = 0;
};

namespace float_replay_detail {

// "-12.34567" with `decimals` digits: integer arithmetic only (printf's float support would pull
// newlib's dtoa and its heap into the image). NaN as an empty cell.
inline std::size_t put_fixed(char* out, double v, int decimals) {
  if (std::isnan(v)) return 0;
  std::size_t n = 0;
  if (v < 0) {
    out[n++] = '-';
    v = -v;
  }
  long long scale = 1;
  for (int i = 0; i < decimals; ++i) scale *= 10;
  const long long all = static_cast<long long>(v * static_cast<double>(scale) + 0.5);
  char digits[24];
  int d = 0;
  for (long long whole = all / scale; d == 0 || whole > 0; whole /= 10) digits[d++] = static_cast<char>('0' + whole % 10);
  while (d > 0) out[n++] = digits[--d];
  if (decimals > 0) {
    out[n++] = '.';
    long long frac = all % scale;
    for (long long div = scale / 10; div > 0; div /= 10) {
      out[n++] = static_cast<char>('0' + frac / div);
      frac %= div;
    }
  }
  return n;
}

}  // namespace float_replay_detail

// The CSV's header; its rows follow it.
inline constexpr std::string_view kFloatReplayHeader =
    "time_s,est_stator_winding_c,est_stator_core_c,est_rotor_winding_c,est_rotor_core_c,"
    "std_stator_winding_k,std_stator_core_k,std_rotor_winding_k,std_rotor_core_k,cooling_factor,cooling_factor_std,"
    "cooling_alarm\n";

template <class Io>
FloatReplayResult run_float_replay(Io& io, Estimator<float>& estimator) {
  using float_replay_detail::put_fixed;
  FloatReplayResult result;
  ReplayClock<float> clock(estimator);
  io.write(kFloatReplayHeader.data(), kFloatReplayHeader.size());
  auto row = [&io](const EstimatorOutput<float>& o, TimeUs first_us) {
    char line[256];
    std::size_t n = put_fixed(line, static_cast<double>(o.time_us - first_us) / kUsPerS, 1);
    for (int i = 0; i < kNumNodes; ++i) {
      line[n++] = ',';
      n += put_fixed(line + n, static_cast<double>(o.node_c[i]), 5);
    }
    for (int i = 0; i < kNumNodes; ++i) {
      line[n++] = ',';
      n += put_fixed(line + n, static_cast<double>(o.node_std_k[i]), 5);
    }
    line[n++] = ',';
    n += put_fixed(line + n, static_cast<double>(o.cooling_factor), 5);
    line[n++] = ',';
    n += put_fixed(line + n, static_cast<double>(o.cooling_factor_std), 5);
    line[n++] = ',';
    line[n++] = o.cooling_alarm ? '1' : '0';
    line[n++] = '\n';
    io.write(line, n);
  };
  static char chunk[4096];
  static char line[520];
  std::size_t line_len = 0;
  bool too_long = false;
  auto take_line = [&] {
    if (too_long || line_len == 0) {
      result.bad_lines += too_long ? 1 : 0;
      return;
    }
    CandumpRecord rec;
    if (parse_candump_line(std::string_view(line, line_len), rec) != nullptr) {
      ++result.bad_lines;
      return;
    }
    io.tick_started();
    clock.frame(rec.time_us, rec.frame, [&](const EstimatorOutput<float>& o, TimeUs first_us) {
      io.tick_ended();
      row(o, first_us);
      io.tick_started();
    });
    io.tick_ended();
  };
  for (std::size_t got; (got = io.read(chunk, sizeof chunk)) > 0;) {
    for (std::size_t i = 0; i < got; ++i) {
      if (chunk[i] == '\n') {
        take_line();
        line_len = 0;
        too_long = false;
      } else if (line_len < sizeof line) {
        line[line_len++] = chunk[i];
      } else {
        too_long = true;
      }
    }
  }
  take_line();
  clock.finish(row);
  result.counts = clock.counts();
  return result;
}

}  // namespace lptn::fw
