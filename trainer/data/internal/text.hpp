#pragma once
// printf-style formatting for messages (no std::format in the oldest supported libstdc++).

#include <cstdarg>
#include <cstdio>
#include <string>
#include <string_view>

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

namespace lptn::data::internal {

// A header name as UTF-8. Spreadsheet exports on Windows write Windows-1252 ("T_Wicklung [°C]"
// with a single byte 0xB0), which a data map (TOML, UTF-8 only) cannot spell; such a name is read
// as Latin-1, every byte its own code point, so that the map names it in UTF-8. Valid UTF-8 is kept.
inline std::string utf8_name(std::string_view s) {
  // Well-formed UTF-8 (Unicode's table 3-7): no overlong forms, no surrogates, nothing past U+10FFFF.
  const auto valid_utf8 = [&] {
    for (std::size_t i = 0; i < s.size();) {
      const auto c = static_cast<unsigned char>(s[i]);
      if (c < 0x80) {
        ++i;
        continue;
      }
      std::size_t n = 0;
      unsigned char lo = 0x80, hi = 0xBF;  // the second byte's range
      if (c >= 0xC2 && c <= 0xDF) {
        n = 2;
      } else if (c >= 0xE0 && c <= 0xEF) {
        n = 3;
        if (c == 0xE0) lo = 0xA0;
        if (c == 0xED) hi = 0x9F;
      } else if (c >= 0xF0 && c <= 0xF4) {
        n = 4;
        if (c == 0xF0) lo = 0x90;
        if (c == 0xF4) hi = 0x8F;
      } else {
        return false;
      }
      if (i + n > s.size()) return false;
      const auto second = static_cast<unsigned char>(s[i + 1]);
      if (second < lo || second > hi) return false;
      for (std::size_t k = 2; k < n; ++k)
        if ((static_cast<unsigned char>(s[i + k]) >> 6) != 0x2) return false;
      i += n;
    }
    return true;
  };
  if (valid_utf8()) return std::string(s);
  std::string out;
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x80) {
      out += ch;
    } else {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  return out;
}

}  // namespace lptn::data::internal
