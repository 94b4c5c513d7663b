#include "can/codegen/cxx_text.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>

namespace lptn::codegen {
namespace {

// UTF-8 to code points; the readers hand over valid UTF-8 (a Latin-1 file converted).
std::vector<char32_t> code_points(std::string_view s) {
  std::vector<char32_t> out;
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    int n = c < 0x80 ? 1 : c < 0xE0 ? 2 : c < 0xF0 ? 3 : 4;
    char32_t cp = n == 1 ? c : n == 2 ? (c & 0x1F) : n == 3 ? (c & 0x0F) : (c & 0x07);
    for (int k = 1; k < n && i + static_cast<std::size_t>(k) < s.size(); ++k)
      cp = (cp << 6) | (static_cast<unsigned char>(s[i + static_cast<std::size_t>(k)]) & 0x3F);
    out.push_back(cp);
    i += static_cast<std::size_t>(n);
  }
  return out;
}

// What Python's str.split() splits at: Unicode white space.
bool is_space(char32_t c) {
  return (c >= 0x09 && c <= 0x0D) || (c >= 0x1C && c <= 0x20) || c == 0x85 || c == 0xA0 || c == 0x1680 ||
         (c >= 0x2000 && c <= 0x200A) || c == 0x2028 || c == 0x2029 || c == 0x202F || c == 0x205F || c == 0x3000;
}

}  // namespace

std::string shortest_double(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v < 0 ? "-inf" : "inf";
  if (v == 0) return std::signbit(v) ? "-0.0" : "0.0";
  char buf[64];
  const auto end = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::scientific).ptr;
  const std::string text(buf, end);  // [-]d[.ddd]e(+|-)XX, the fewest digits that read back
  const bool negative = text[0] == '-';
  const std::size_t e = text.find('e');
  std::string digits;
  for (std::size_t i = negative ? 1 : 0; i < e; ++i)
    if (text[i] != '.') digits += text[i];
  const int exponent = std::atoi(text.c_str() + e + 1);
  const int point = exponent + 1;  // value = 0.DIGITS * 10^point
  std::string out = negative ? "-" : "";
  if (point > -4 && point <= 16) {
    // Appended piece by piece: GCC 12 warns (-Wrestrict, PR 105329) on "0." + std::string(...).
    if (point <= 0) {
      out.append("0.").append(static_cast<std::size_t>(-point), '0').append(digits);
    } else if (static_cast<std::size_t>(point) >= digits.size()) {
      out.append(digits).append(static_cast<std::size_t>(point) - digits.size(), '0').append(".0");
    } else {
      out.append(digits, 0, static_cast<std::size_t>(point)).append(".").append(digits, static_cast<std::size_t>(point));
    }
    return out;
  }
  out.append(digits, 0, 1);
  if (digits.size() > 1) out.append(".").append(digits, 1);
  char exp[16];
  std::snprintf(exp, sizeof exp, "e%c%02d", exponent < 0 ? '-' : '+', std::abs(exponent));
  return out + exp;
}

std::string string_literal(std::string_view utf8) {
  std::string out = "\"";
  for (const char ch : utf8) {
    const auto byte = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (byte >= 0x20 && byte < 0x7F) {
      out += ch;
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\%03o", byte);
      out += buf;
    }
  }
  return out + "\"";
}

std::string ascii_text(std::string_view utf8) {
  std::string out;
  bool pending_space = false;
  for (const char32_t c : code_points(utf8)) {
    if (is_space(c)) {
      pending_space = !out.empty();
      continue;
    }
    if (pending_space) out += ' ';
    pending_space = false;
    char buf[16];
    if (c >= 0x20 && c < 0x7F && c != '\\') {
      out += static_cast<char>(c);
      continue;
    }
    if (c < 0x100)
      std::snprintf(buf, sizeof buf, "\\x%02x", static_cast<unsigned>(c));
    else if (c < 0x10000)
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
    else
      std::snprintf(buf, sizeof buf, "\\U%08x", static_cast<unsigned>(c));
    out += buf;
  }
  return out;
}

std::vector<std::string> comment_lines(std::string_view utf8, const std::string& indent, std::size_t width) {
  const std::string text = ascii_text(utf8);
  const std::size_t room = width - indent.size() - 3;
  std::vector<std::string> lines;
  std::string line;
  // Greedy, as Python's textwrap (no long word broken, none at a hyphen): a word goes on the line if
  // it fits after a space, else it starts the next; a word longer than the room has a line of its own.
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t space = text.find(' ', pos);
    if (space == std::string::npos) space = text.size();
    const std::string word = text.substr(pos, space - pos);
    pos = space + 1;
    if (line.empty()) {
      line = word;
    } else if (line.size() + 1 + word.size() <= room) {
      line += " " + word;
    } else {
      lines.push_back(indent + "// " + line);
      line = word;
    }
  }
  if (!line.empty()) lines.push_back(indent + "// " + line);
  return lines;
}

std::string int_literal(std::int64_t value, bool is_signed) {
  if (value == INT64_MIN) return "(-9223372036854775807 - 1)";
  return std::to_string(value) + (is_signed ? "" : "u");
}
std::string uint_literal(std::uint64_t value) { return std::to_string(value) + "u"; }

std::string hex_mask(int width) {
  const std::uint64_t mask = width >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << width) - 1;
  std::string digits = hex_upper(mask);
  const std::size_t want = static_cast<std::size_t>(std::max(2, (width + 3) / 4));
  if (digits.size() < want) digits.insert(0, want - digits.size(), '0');
  return "0x" + digits + "u";
}

std::string hex_upper(std::uint64_t value) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%llX", static_cast<unsigned long long>(value));
  return buf;
}

}  // namespace lptn::codegen
