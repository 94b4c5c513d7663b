// A byte's value as a hexadecimal digit, for the text logs' parsers (candump here, ASC on the
// host): one load a digit, where three ranges tested in turn were a branch a range (a log's data
// digits are as often letters as numbers).
#pragma once

#include <cstdint>

namespace lptn::fw {

namespace hex_digit_detail {
struct HexValues {
  std::int8_t of[256];
  constexpr HexValues() : of() {
    for (int c = 0; c < 256; ++c)
      of[c] = static_cast<std::int8_t>(c >= '0' && c <= '9'   ? c - '0'
                                       : c >= 'a' && c <= 'f' ? c - 'a' + 10
                                       : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                                              : -1);
  }
};
inline constexpr HexValues kHexValues{};
}  // namespace hex_digit_detail

// 0..15 for '0'-'9', 'a'-'f', 'A'-'F'; -1 for any other byte.
inline int hex_value(char c) { return hex_digit_detail::kHexValues.of[static_cast<unsigned char>(c)]; }

}  // namespace lptn::fw
