// A signal's [min|max] as raw values, in exact arithmetic: (min - offset) / factor on the numbers as
// written (a double would move a bound of 0.1 / 0.1 off 1), so that the range check and the
// generated NAME_is_in_range() decide on the file's values, not on their nearest doubles.
// Internal to can/dbc.
#pragma once

#include <string>

#include "can/dbc/internal/parser.hpp"

namespace lptn::dbc::internal {

struct ExactRange {
  bool min_above_max = false;     // minimum > maximum
  bool no_range = false;          // [0|0]
  std::string low_text, high_text;  // the raw bounds (sorted): an integer's digits, else %g
  bool exceeds_bits = false;      // a bound beyond what the signal's bits hold
  bool holds_no_value = false;    // no whole raw value within the bounds and the bits
  long double low = 0, high = 0;  // ceil(low), floor(high), clamped to +-2^64
};

// raw_low/raw_high: what the signal's bits hold (up to 2^64 - 1, so as long doubles: exact).
ExactRange exact_range(const Number& factor, const Number& offset, const Number& minimum, const Number& maximum,
                       long double raw_low, long double raw_high);

}  // namespace lptn::dbc::internal
