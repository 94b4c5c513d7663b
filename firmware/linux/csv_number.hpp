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


// "%.9g": nine significant digits of the exact binary value, rounded half to even, in fixed
// notation while the rounded value's decimal exponent X is in [-4, 9), without trailing zeros:
// what every input and reading of a CAN log is. Done here in 128-bit integers, as "%.6f" is: |v| =
// m 2^e times 10^(8 - X), rounded exactly, is the nine digits (at most 2^53 10^13 < 2^97). Outside
// that range (and for infinities and NaN) std::to_chars's general format, which prints as printf
// does (what the standard asks of it); for every value it took a seventh of `lptn replay`'s time.
inline char* put_general9(char* out, double v) {
  auto general = [&] { return std::to_chars(out, out + kMaxChars, v, std::chars_format::general, 9).ptr; };
  const double a = std::fabs(v);
  if (a == 0.0) {
    if (std::signbit(v)) *out++ = '-';
    *out++ = '0';
    return out;
  }
  if (!(a >= 1e-5 && a < 1e9)) return general();
  // 10^k, k = 0..13, exact in 64 bits.
  static constexpr std::uint64_t kTen[14] = {1ull,
                                             10ull,
                                             100ull,
                                             1000ull,
                                             10000ull,
                                             100000ull,
                                             1000000ull,
                                             10000000ull,
                                             100000000ull,
                                             1000000000ull,
                                             10000000000ull,
                                             100000000000ull,
                                             1000000000000ull,
                                             10000000000000ull};
  static constexpr double kDecade[14] = {1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8};
  std::uint64_t m;
  int e;
  detail::decompose(a, m, e);
  // A first guess at floor(log10 a) from the doubles nearest the decades; the count of digits
  // below says whether it was right (a next to a decade may be guessed one off either way).
  int x = -5;
  while (x < 8 && a >= kDecade[x + 6]) ++x;
  std::uint64_t n = 0;
  for (int tries = 0; tries < 3; ++tries) {
    n = detail::scaled_round(m, e, kTen[8 - x]);
    if (n < kTen[8] && x > -5) {
      --x;  // a below 10^x: a digit short
    } else if (n > kTen[9] && x < 8) {
      ++x;  // a at or above 10^(x+1): a digit too many (exactly 10^9 is the rounding's carry)
    } else {
      break;
    }
  }
  if (n < kTen[8] || n > kTen[9]) return general();
  if (n == kTen[9]) {  // rounded up into the next decade: 1.00000000 10^(x+1)
    n = kTen[8];
    ++x;
  }
  if (x < -4 || x >= 9) return general();
  char digits[9];
  for (int i = 8; i >= 0; --i) {
    digits[i] = static_cast<char>('0' + n % 10);
    n /= 10;
  }
  int last = 8;  // the last digit kept: trailing zeros go
  while (last > 0 && digits[last] == '0') --last;
  if (std::signbit(v)) *out++ = '-';
  if (x >= 0) {
    for (int i = 0; i <= x; ++i) *out++ = digits[i];
    if (last > x) {
      *out++ = '.';
      for (int i = x + 1; i <= last; ++i) *out++ = digits[i];
    }
  } else {
    *out++ = '0';
    *out++ = '.';
    for (int i = -1; i > x; --i) *out++ = '0';
    for (int i = 0; i <= last; ++i) *out++ = digits[i];
  }
  return out;
}

}  // namespace lptn::fw::csv_number
