// candump's log format (`candump -L`, what canplayer plays): one frame per line,
//     (1700000000.123456) can0 101#0A1B2C3D00000005
//   id: 3 hex digits standard, 8 extended; with bit 29 (0x20000000) set, an error frame
//   data: hex bytes; `R` (optionally a length digit) for a remote frame;
//   CAN FD: `##` then one flags nibble, then the data;
//   optionally a direction after the frame, ` R` (received) or ` T` (sent), as newer can-utils and
//   python-can write it.
// Parsing takes a string_view and allocates nothing, so the daemon and the bare-metal replay image
// read logs on the target.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string_view>

#include "lptn/firmware/can_frame.hpp"
#include "lptn/firmware/hex_digit.hpp"
#include "lptn/firmware/input.hpp"

namespace lptn::fw {

struct CandumpRecord {
  TimeUs time_us = 0;
  std::string_view interface;  // points into the parsed line
  CanFrame frame;
};

namespace candump_detail {

// Digits only, at most `max_digits`, into an integer; false on anything else or an empty field.
inline bool decimal(std::string_view s, std::size_t max_digits, long long& out) {
  if (s.empty() || s.size() > max_digits) return false;
  out = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
    out = out * 10 + (c - '0');
  }
  return true;
}

constexpr std::uint32_t kErrorFlag = 0x20000000u;

// s[pos, pos + n) for pos <= s.size(): string_view::substr would check pos and, without
// exceptions, reach abort() and with it newlib's heap (the bare-metal image has none).
inline std::string_view part(std::string_view s, std::size_t pos, std::size_t n = std::string_view::npos) {
  const std::size_t left = s.size() - pos;
  return std::string_view(s.data() + pos, n < left ? n : left);
}

// The first `c` in s from `from` on, or s.size(): string_view::find, as a loop over the few bytes
// of a candump field (find calls memchr, whose start costs more than these fields' length).
inline std::size_t first_of(std::string_view s, char c, std::size_t from = 0) {
  while (from < s.size() && s[from] != c) ++from;
  return from;
}

// candump's own time stamp, "(%010lu.%06lu) ": the seconds and microseconds at their places, their
// sixteen digits tested and summed without a branch a digit. False for any other stamp (fewer or
// more digits of seconds, as python-can writes relative times), which the general parse reads
// to the same value or the same complaint.
inline bool fixed_width_stamp(std::string_view line, TimeUs& time_us) {
  if (line.size() < 20 || line[0] != '(' || line[11] != '.' || line[18] != ')' || line[19] != ' ') return false;
  unsigned not_digit = 0;
  auto digits = [&](int first, int last) {  // line[first..last] as a number, not_digit marking any other byte
    long long value = 0;
    for (int i = first; i <= last; ++i) {
      const unsigned d = static_cast<unsigned char>(line[i]) - static_cast<unsigned>('0');
      not_digit |= d > 9 ? 1u : 0u;
      value = value * 10 + d;
    }
    return value;
  };
  const long long sec = digits(1, 10), usec = digits(12, 17);
  if (not_digit != 0) return false;
  time_us = static_cast<TimeUs>(sec) * kUsPerS + static_cast<TimeUs>(usec);
  return true;
}

}  // namespace candump_detail

// Parses one line (without its newline; a trailing '\r' is accepted). Returns nullptr on success,
// every field of `out` set; otherwise a static string saying what is wrong (for "FILE:LINE:
// reason"), and `out` partly written. The frame is made in `out` itself: made aside and copied, a
// frame (72 bytes) was cleared and copied twice a line on the way to the replay.
inline const char* parse_candump_line(std::string_view line, CandumpRecord& out) {
  using namespace candump_detail;
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  // (sec.usec)
  std::size_t close = 18;
  if (!fixed_width_stamp(line, out.time_us)) {
    if (line.size() < 3 || line.front() != '(') return "expected '(seconds.microseconds)' at the start";
    close = line.find(')');
    if (close == std::string_view::npos) return "time stamp has no closing ')'";
    const std::string_view stamp = part(line, 1, close - 1);
    const std::size_t dot = stamp.find('.');
    long long sec = 0, usec = 0;
    if (dot == std::string_view::npos || !decimal(part(stamp, 0, dot), 12, sec) || stamp.size() - dot - 1 != 6 ||
        !decimal(part(stamp, dot + 1), 6, usec))
      return "time stamp is not seconds.microseconds (six digits)";
    out.time_us = static_cast<TimeUs>(sec) * kUsPerS + static_cast<TimeUs>(usec);
  }

  // interface
  std::string_view rest = part(line, close + 1);
  if (rest.empty() || rest.front() != ' ') return "expected a space after the time stamp";
  rest.remove_prefix(1);
  const std::size_t space = first_of(rest, ' ');
  if (space == rest.size() || space == 0) return "expected an interface name and a frame";
  out.interface = part(rest, 0, space);
  std::string_view frame = part(rest, space + 1);
  while (!frame.empty() && frame.back() == ' ') frame.remove_suffix(1);
  // can-utils' and python-can's newer logs end with the direction: " R" received, " T" sent.
  if (frame.size() > 2 && frame[frame.size() - 2] == ' ' && (frame.back() == 'R' || frame.back() == 'T')) {
    frame.remove_suffix(2);
    while (!frame.empty() && frame.back() == ' ') frame.remove_suffix(1);
  }

  // id#data
  const std::size_t hash = first_of(frame, '#');
  if (hash == frame.size()) return "frame has no '#' between id and data";
  const std::string_view id = part(frame, 0, hash);
  if (id.size() != 3 && id.size() != 8) return "frame id must have 3 (standard) or 8 (extended) hex digits";
  std::uint32_t value = 0;
  for (char c : id) {
    const int v = hex_value(c);
    if (v < 0) return "frame id is not hexadecimal";
    value = value << 4 | static_cast<std::uint32_t>(v);
  }
  CanFrame& f = out.frame;
  f = CanFrame{};
  f.extended = id.size() == 8;
  f.error = f.extended && (value & kErrorFlag) != 0;
  f.id = f.extended ? (value & 0x1FFFFFFFu) : value;
  if (!f.extended && value > 0x7FF) return "standard frame id above 7FF";
  std::string_view data = part(frame, hash + 1);
  std::size_t max_len = 8;
  if (!data.empty() && data.front() == '#') {  // CAN FD: flags nibble, then data
    if (data.size() < 2 || hex_value(data[1]) < 0) return "CAN FD frame has no flags digit after '##'";
    f.fd = true;
    max_len = 64;
    data.remove_prefix(2);
  } else if (!data.empty() && (data.front() == 'R' || data.front() == 'r')) {
    f.remote = true;
    if (data.size() == 2 && data[1] >= '0' && data[1] <= '8') {
      f.len = static_cast<std::uint8_t>(data[1] - '0');
    } else if (data.size() != 1) {
      return "remote frame: 'R' may only be followed by a length digit 0-8";
    }
    return nullptr;
  }
  if (data.size() % 2 != 0) return "data has an odd number of hex digits";
  if (data.size() / 2 > max_len) return f.fd ? "CAN FD data longer than 64 bytes" : "data longer than 8 bytes";
  for (std::size_t i = 0; i < data.size(); i += 2) {
    const int hi = hex_value(data[i]), lo = hex_value(data[i + 1]);
    if ((hi | lo) < 0) return "data is not hexadecimal";
    f.data[i / 2] = static_cast<std::uint8_t>(hi << 4 | lo);
  }
  f.len = static_cast<std::uint8_t>(data.size() / 2);
  return nullptr;
}

// Writes one line (no newline) into buf; returns its length, or 0 if buf is too small (120 bytes
// always suffice for classic CAN, 200 for FD).
inline std::size_t format_candump_line(char* buf, std::size_t size, TimeUs time_us, std::string_view interface,
                                       const CanFrame& f) {
  using candump_detail::kErrorFlag;
  const long long sec = time_us / kUsPerS, usec = time_us % kUsPerS;
  // A buffer too small is the caller's to find out from the 0 this returns: inlined into a caller
  // that passes one on purpose, GCC would warn about the truncation it checks for.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-truncation"
#endif
  const int n = std::snprintf(buf, size, "(%010lld.%06lld) ", sec, usec);
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
  if (n < 0 || static_cast<std::size_t>(n) >= size) return 0;
  std::size_t at = static_cast<std::size_t>(n);
  // The name's bytes as they are, then a space: "%.*s" would stop at a NUL byte, which a parsed
  // line's name may hold, and the line would no longer parse to the same frame.
  if (size - at <= interface.size() + 1) return 0;
  std::memcpy(buf + at, interface.data(), interface.size());
  at += interface.size();
  buf[at++] = ' ';
  buf[at] = '\0';
  auto put = [&](const char* fmt, unsigned v) {
    const int k = std::snprintf(buf + at, size - at, fmt, v);
    if (k < 0 || at + static_cast<std::size_t>(k) >= size) return false;
    at += static_cast<std::size_t>(k);
    return true;
  };
  const std::uint32_t id = f.error ? (f.id | kErrorFlag) : f.id;
  if (!put(f.extended || f.error ? "%08X#" : "%03X#", id)) return 0;
  if (f.remote) return put(f.len ? "R%u" : "R", f.len) ? at : 0;
  if (f.fd && !put("#%X", 0u)) return 0;
  for (unsigned i = 0; i < f.len; ++i)
    if (!put("%02X", f.data[i])) return 0;
  return at;
}

}  // namespace lptn::fw
