#pragma once
// printf-style formatting for messages (no std::format in the oldest supported libstdc++).

#include <cstdarg>
#include <cstdio>
#include <string>

namespace lptn::data::internal {

#if defined(__GNUC__)
__attribute__((format(printf, 1, 2)))
#endif
inline std::string strf(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  va_list copy;
  va_copy(copy, args);
  const int n = std::vsnprintf(nullptr, 0, fmt, copy);
  va_end(copy);
  std::string out;
  if (n > 0) {
    out.resize(static_cast<std::size_t>(n) + 1);
    std::vsnprintf(out.data(), out.size(), fmt, args);
    out.resize(static_cast<std::size_t>(n));
  }
  va_end(args);
  return out;
}

// A time or value as a person would write it: up to 3 decimals, no trailing zeros ("12.5", "100").
inline std::string num(double v) {
  std::string s = strf("%.3f", v);
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

}  // namespace lptn::data::internal

