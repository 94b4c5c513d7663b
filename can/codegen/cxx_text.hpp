// Text of generated C++: literals, comments and numbers, written so that a header is ASCII whatever
// the DBC's text, and each number reads back as the double it came from.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace lptn::codegen {

// The shortest text that reads back as `v`, in Python's repr() form ("0.1", "1.0", "1e-05",
// "1e+16"): the generated headers have always spelled doubles so.
std::string shortest_double(double v);
// "\"...\"": printable ASCII as is, '"' and '\\' escaped, every other byte of the UTF-8 an octal escape
// (a \x escape would swallow hex digits after it).
std::string string_literal(std::string_view utf8);
// Whitespace runs as one space; printable ASCII as is; the backslash and every other code point as
// \xNN, \uNNNN or \UNNNNNNNN (a backslash at the end of a // line would splice the next line in).
std::string ascii_text(std::string_view utf8);
// `text` as // lines of at most `width` columns after `indent`, broken at spaces only.
std::vector<std::string> comment_lines(std::string_view utf8, const std::string& indent, std::size_t width = 100);
// A C++ integer literal: "12u" unsigned; INT64_MIN as an expression (its literal does not exist).
std::string int_literal(std::int64_t value, bool is_signed);
std::string uint_literal(std::uint64_t value);
// 0xFFu-style mask of `width` bits, at least two hex digits.
std::string hex_mask(int width);
std::string hex_upper(std::uint64_t value);  // "1A2" (no 0x)

}  // namespace lptn::codegen
