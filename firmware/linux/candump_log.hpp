// candump's log format (`candump -L`, what canplayer plays): one frame per line,
//     (1700000000.123456) can0 101#0A1B2C3D00000005
//   id: 3 hex digits standard, 8 extended; with bit 29 (0x20000000) set, an error frame
//   data: hex bytes; `R` (optionally a length digit) for a remote frame;
//   CAN FD: `##` then one flags nibble, then the data;
//   optionally a direction after the frame, ` R` (received) or ` T` (sent), as newer can-utils and
//   python-can write it.
// Parsing takes a string_view and allocates nothing, so the daemon can read logs on the target.
#pragma once

#include <cstddef>
#include <string_view>

#include "lptn/firmware/can_frame.hpp"
#include "lptn/firmware/input.hpp"

namespace lptn::fw {

struct CandumpRecord {
  TimeUs time_us = 0;
  std::string_view interface;  // points into the parsed line
  CanFrame frame;
};

// Parses one line (without its newline; a trailing '\r' is accepted). Returns nullptr on success,
// otherwise a static string saying what is wrong (for "FILE:LINE: reason").
const char* parse_candump_line(std::string_view line, CandumpRecord& out);

// Writes one line (no newline) into buf; returns its length, or 0 if buf is too small (120 bytes
// always suffice for classic CAN, 200 for FD).
std::size_t format_candump_line(char* buf, std::size_t size, TimeUs time_us, std::string_view interface,
                                const CanFrame& frame);

}  // namespace lptn::fw
