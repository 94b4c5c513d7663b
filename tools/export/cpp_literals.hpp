// Values written as C++ source text that the compiler reads back to exactly the same value.
#pragma once

#include <string>

namespace lptn::exporter {

// The shortest decimal that reads back to exactly `v` (std::to_chars), always a floating literal
// ("24.0", not "24"). Throws std::invalid_argument for NaN and infinities, which have no literal;
// `what` names the value in that message.
std::string double_literal(double v, const std::string& what);
// The same for a float, with the f suffix so that the compiler rounds the decimal straight to
// float (through double it could round twice).
std::string float_literal(float v, const std::string& what);

// A string literal with quotes; anything but printable ASCII as an octal escape (bounded to three
// digits, unlike \x), so the bytes are exact whatever the source character set.
std::string string_literal(const std::string& s);

// Text safe inside a // comment: control characters (a newline would end the comment and let the
// rest run as code) become spaces, and backslashes slashes (one at the line's end would splice the
// next line into the comment). Comments are for people; the exact strings are in the constants.
std::string comment_text(const std::string& s);

}  // namespace lptn::exporter
