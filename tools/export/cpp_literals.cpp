#include "tools/export/cpp_literals.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>

namespace lptn::exporter {
namespace {

template <class F>
std::string shortest(F v, const std::string& what) {
  if (!std::isfinite(v)) throw std::invalid_argument(what + ": " + std::to_string(v) + " has no C++ literal");
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, r.ptr);
  // "24" would be an int literal, "1e+20" is already floating.
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

}  // namespace

std::string double_literal(double v, const std::string& what) { return shortest(v, what); }

std::string float_literal(float v, const std::string& what) { return shortest(v, what) + "f"; }

std::string string_literal(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u >= 0x20 && u < 0x7f) {
      out += c;
    } else {
      out += '\\';
      out += static_cast<char>('0' + (u >> 6));
      out += static_cast<char>('0' + ((u >> 3) & 7));
      out += static_cast<char>('0' + (u & 7));
    }
  }
  return out + "\"";
}

std::string comment_text(const std::string& s) {
  std::string out = s;
  for (char& c : out) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) c = ' ';
    if (c == '\\') c = '/';
  }
  return out;
}

}  // namespace lptn::exporter
