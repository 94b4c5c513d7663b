// Numbers as the estimates' CSV prints them, without printf: printf's "%.6f" and "%.9g" (glibc:
// the exact binary value rounded half to even) took half of `lptn replay`'s time. Each function
// writes the very bytes printf would (tests/replay/test_replay_output.cpp holds them to snprintf on
// a million doubles of every kind and the edge cases) and returns the end; `out` needs kMaxChars
// bytes ("%.6f" of the largest doubles; 32 suffice for magnitudes below 9.2e12 and for "%.9g").
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace lptn::fw::csv_number {

inline constexpr std::size_t kMaxChars = 330;

// The decimal digits of v.
inline char* put_unsigned(char* out, std::uint64_t v) {
  char tmp[20];
  int n = 0;
  do {
    tmp[n++] = static_cast<char>('0' + v % 10);
    v /= 10;
  } while (v != 0);
  while (n) *out++ = tmp[--n];
  return out;
}

// "%d" / "%u".
inline char* put_int(char* out, long long v) {
  if (v < 0) {
    *out++ = '-';
    return put_unsigned(out, static_cast<std::uint64_t>(0) - static_cast<std::uint64_t>(v));
  }
  return put_unsigned(out, static_cast<std::uint64_t>(v));
}

namespace detail {

__extension__ typedef unsigned __int128 u128;  // GCC's and Clang's; -Wpedantic asks for __extension__

// |v| = m 2^e with m < 2^53 (v finite, nonzero, normal).
inline void decompose(double v, std::uint64_t& m, int& e) {
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  const int biased = static_cast<int>(bits >> 52 & 0x7FF);
  m = bits & ((std::uint64_t{1} << 52) - 1);
  if (biased == 0) {
    e = -1074;  // subnormal (or zero)
  } else {
    m |= std::uint64_t{1} << 52;
    e = biased - 1075;
  }
}

// m 2^e 10^k rounded half to even; the caller ensures the result fits in 64 bits and m 10^k <
// 2^99 (so that -e >= 100 rounds to 0).
inline std::uint64_t scaled_round(std::uint64_t m, int e, std::uint64_t ten_k) {
  const u128 scaled = static_cast<u128>(m) * ten_k;
  if (e >= 0) return static_cast<std::uint64_t>(scaled << e);
  if (-e >= 100) return 0;
  const int s = -e;
  const u128 q = scaled >> s, rem = scaled - (q << s), half = static_cast<u128>(1) << (s - 1);
  std::uint64_t n = static_cast<std::uint64_t>(q);
  if (rem > half || (rem == half && (n & 1) != 0)) ++n;
  return n;
}

}  // namespace detail

// "%.6f": |v| * 1e6 rounded half to even, exactly, in 128-bit integers (v = m 2^e, m < 2^53, so
// m 1e6 < 2^73); values of 2^63 / 1e6 or more, infinities and NaN go to std::to_chars, which
// prints as printf does.
inline char* put_fixed6(char* out, double v) {
  if (!(std::fabs(v) < 9.2e12)) return std::to_chars(out, out + kMaxChars, v, std::chars_format::fixed, 6).ptr;
  std::uint64_t m;
  int e;
  detail::decompose(v, m, e);
  const std::uint64_t n = detail::scaled_round(m, e, 1000000);  // |v| < 9.2e12: fits
  if (std::signbit(v)) *out++ = '-';
  out = put_unsigned(out, n / 1000000);
  *out++ = '.';
  std::uint64_t frac = n % 1000000;
  for (int i = 5; i >= 0; --i) {
    out[i] = static_cast<char>('0' + frac % 10);
    frac /= 10;
  }
  return out + 6;
}


// "%.9g": std::to_chars's general format with precision 9 prints as printf does (what the
// standard asks of it), about four times as fast as glibc's printf here.
inline char* put_general9(char* out, double v) {
  return std::to_chars(out, out + kMaxChars, v, std::chars_format::general, 9).ptr;
}

}  // namespace lptn::fw::csv_number
