// Numbers as the estimates' CSV prints them, without printf: printf's "%.6f" and "%.9g" (glibc:
// the exact binary value rounded half to even) took half of `lptn replay`'s time. Each function
// writes the very bytes printf would (tests/replay/test_replay_output.cpp holds them to snprintf on
// a million doubles of every kind and the edge cases) and returns the end; `out` needs kMaxChars
// bytes ("%.6f" of the largest doubles; 32 suffice for magnitudes below 9.2e12 and for "%.9g").
// The numbers of a row (below 1000, or nine digits within [1e-5, 1e9)) are made in registers,
// ShortText, from pairs of digits out of a table, rounded by a multiplication in double where it
// is certain to round as the exact value does: a row's numbers took a fifth less time than digit by
// digit from an exact 128-bit product (docs/benchmarks.md).
#pragma once

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace lptn::fw::csv_number {

inline constexpr std::size_t kMaxChars = 330;

namespace detail {

// "00" to "99": two digits' text at 2 v.
inline constexpr char kDigitPairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";
static_assert(std::endian::native == std::endian::little, "a text's first byte is its word's lowest");

// The two digits of v < 100 as text in the low 16 bits.
inline std::uint64_t pair_text(std::uint64_t v) {
  std::uint16_t pair;
  std::memcpy(&pair, kDigitPairs + 2 * v, sizeof pair);
  return pair;
}

// The six digits of v < 10^6, leading zeros included, as text in the low 48 bits.
inline std::uint64_t six_digits_text(std::uint64_t v) {
  const std::uint64_t hundreds = v / 100;
  return pair_text(v / 10000) | pair_text(hundreds % 100) << 16 | pair_text(v - hundreds * 100) << 32;
}

}  // namespace detail

// The decimal digits of v. One or two digits (every flag and count of a row) from the table.
inline char* put_unsigned(char* out, std::uint64_t v) {
  if (v < 10) {
    *out = static_cast<char>('0' + v);
    return out + 1;
  }
  if (v < 100) {
    std::memcpy(out, detail::kDigitPairs + 2 * v, 2);
    return out + 2;
  }
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

// a 10^k rounded half to even, as scaled_round has it for a's m and e, for 0 <= a 10^k < 2^47 (k
// <= 13, so 10^k is a double): the double product is within half its ulp, at most 2^-7, of the
// exact one, so it rounds as the exact one does unless its fraction lies within 0.01 of a half;
// only then the exact way.
inline std::uint64_t round_scaled(double a, double ten_k_double, std::uint64_t ten_k) {
  const double r = a * ten_k_double;
  const std::int64_t below = static_cast<std::int64_t>(r);
  const double fraction = r - static_cast<double>(below);  // exact
  if (fraction > 0.49 && fraction < 0.51) [[unlikely]] {
    std::uint64_t m;
    int e;
    decompose(a, m, e);
    return scaled_round(m, e, ten_k);
  }
  return static_cast<std::uint64_t>(below) + (fraction > 0.5 ? 1 : 0);
}

inline constexpr std::uint64_t kAsciiZeros = 0x3030303030303030;  // '0' in every byte

}  // namespace detail

// A number's text made in registers, its first byte the lowest, and its length (-1: not made here;
// the put_ functions below write it). A caller that keeps a copy of the text stores the registers
// twice: bytes read back just after they were stored in pieces wait for the stores to be done (a
// load is forwarded from one store only), and that copy was a fifth of a CSV cell's time.
struct ShortText {
  detail::u128 bytes = 0;
  int length = -1;
};

// Stores a made text at `out` (16 bytes, whatever its length) and returns its end.
inline char* put_short(char* out, const ShortText& t) {
  std::memcpy(out, &t.bytes, sizeof t.bytes);
  return out + t.length;
}

// A made text of |v| with v's sign before it: printf writes '-' for every negative sign, -0 and
// numbers that round to zero included.
inline ShortText signed_text(ShortText t, double v) {
  if (std::signbit(v)) {
    t.bytes = t.bytes << 8 | '-';
    ++t.length;
  }
  return t;
}

// "%.6f" of |v| below 999.9999995 (every temperature, spread and margin): the whole part by its
// count of digits, a branch each (the length is then known as soon as the branch is predicted).
inline ShortText fixed6_short(double v) {
  ShortText t;
  const double a = std::fabs(v);
  if (!(a < 1000.0)) return t;
  const std::uint64_t n = detail::round_scaled(a, 1e6, 1000000);
  const std::uint64_t whole = n / 1000000;
  const std::uint64_t point_decimals = '.' | detail::six_digits_text(n - whole * 1000000) << 8;  // seven bytes
  using detail::u128;
  if (whole < 10) {
    t.bytes = ('0' + whole) | point_decimals << 8;
    t.length = 8;
  } else if (whole < 100) {
    t.bytes = detail::pair_text(whole) | static_cast<u128>(point_decimals) << 16;
    t.length = 9;
  } else if (whole < 1000) {
    t.bytes = ('0' + whole / 100) | detail::pair_text(whole % 100) << 8 | static_cast<u128>(point_decimals) << 24;
    t.length = 10;
  } else {
    return t;  // 999.9999995 and above round up to 1000
  }
  return signed_text(t, v);
}

// "%.6f": |v| * 1e6 rounded half to even, exactly, in 128-bit integers (v = m 2^e, m < 2^53, so
// m 1e6 < 2^73); values of 2^63 / 1e6 or more, infinities and NaN go to std::to_chars, which
// prints as printf does.
inline char* put_fixed6(char* out, double v) {
  if (const ShortText t = fixed6_short(v); t.length >= 0) return put_short(out, t);
  if (!(std::fabs(v) < 9.2e12)) return std::to_chars(out, out + kMaxChars, v, std::chars_format::fixed, 6).ptr;
  std::uint64_t m;
  int e;
  detail::decompose(v, m, e);
  const std::uint64_t n = detail::scaled_round(m, e, 1000000);  // |v| < 9.2e12: fits
  if (std::signbit(v)) *out++ = '-';
  out = put_unsigned(out, n / 1000000);
  *out++ = '.';
  const std::uint64_t decimals = detail::six_digits_text(n % 1000000);
  std::memcpy(out, &decimals, sizeof decimals);  // 8 bytes, 2 past the end: `out` has kMaxChars
  return out + 6;
}


// "%.9g": nine significant digits of the exact binary value, rounded half to even, in fixed
// notation while the rounded value's decimal exponent X is in [-4, 9), without trailing zeros:
// what every input and reading of a CAN log is: |v| times 10^(8 - X) rounded half to even
// (round_scaled: in double, or exactly in 128-bit integers where the double could round otherwise;
// at most 2^53 10^13 < 2^97) is the nine digits. Outside that range (and for infinities and NaN)
// std::to_chars's general format, which prints as printf does (what the standard asks of it); for
// every value it took a seventh of `lptn replay`'s time. general9_short makes the text in that
// range (and of zeros); put_general9 writes any double.
inline ShortText general9_short(double v) {
  ShortText t;
  const double a = std::fabs(v);
  if (a == 0.0) {
    t.bytes = '0';
    t.length = 1;
    return signed_text(t, v);
  }
  if (!(a >= 1e-5 && a < 1e9)) return t;
  // 10^k, k = 0..13, exact in 64 bits and in a double.
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
  static constexpr double kTenDouble[14] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13};
  static constexpr double kDecade[14] = {1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8};
  // floor(log10 a), first from the binary exponent (a >= 2^e2, whose floor(log10) is a's or one
  // less), then against the double nearest the next decade; the count of digits below says whether
  // it was right (a next to a decade may be guessed one off either way).
  std::uint64_t bits;
  std::memcpy(&bits, &a, sizeof bits);
  const int e2 = static_cast<int>(bits >> 52) - 1023;  // a normal: a in [2^e2, 2^(e2 + 1))
  int x = (e2 * 1262611) >> 22;                        // 1262611 / 2^22 is log10(2) to 8e-8; >> floors
  x = x < -5 ? -5 : (x > 8 ? 8 : x);
  if (x < 8 && a >= kDecade[x + 6]) ++x;
  auto nine_digits = [&] { return detail::round_scaled(a, kTenDouble[8 - x], kTen[8 - x]); };
  std::uint64_t n = nine_digits();
  if (n < kTen[8] && x > -5) {
    --x;  // a below 10^x: a digit short
    n = nine_digits();
  } else if (n > kTen[9] && x < 8) {
    ++x;  // a at or above 10^(x+1): a digit too many (exactly 10^9 is the rounding's carry)
    n = nine_digits();
  }
  if (n < kTen[8] || n > kTen[9]) return t;
  if (n == kTen[9]) {  // rounded up into the next decade: 1.00000000 10^(x+1)
    n = kTen[8];
    ++x;
  }
  if (x < -4 || x >= 9) return t;
  // The nine digits as text, the first in the lowest byte; the last one kept is the last nonzero
  // (trailing zeros go; the bytes past the length are left as they are), or the units digit in
  // fixed notation.
  using detail::pair_text;
  using detail::u128;
  const std::uint64_t first = n / kTen[8], rest = n - first * kTen[8];
  const std::uint64_t high = rest / 10000, low = rest - high * 10000, high2 = high / 100, low2 = low / 100;
  const std::uint64_t eight = pair_text(high2) | pair_text(high - high2 * 100) << 16 | pair_text(low2) << 32 |
                              pair_text(low - low2 * 100) << 48;
  const std::uint64_t values = eight - detail::kAsciiZeros;  // each byte its digit's value
  const int last = values == 0 ? 0 : 8 - std::countl_zero(values) / 8;
  const u128 digits = ('0' + first) | static_cast<u128>(eight) << 8;
  if (x >= 0 && last > x) {  // d.ddd: the dot after the units digit
    const u128 units = digits & ((u128{1} << (8 * (x + 1))) - 1);
    t.bytes = units | u128{'.'} << (8 * (x + 1)) | (digits ^ units) << 8;
    t.length = last + 2;
  } else if (x >= 0) {  // ddd
    t.bytes = digits;
    t.length = x + 1;
  } else {  // 0.000ddd: "0." and -x - 1 zeros before the digits
    const int prefix = 1 - x;
    const std::uint64_t zero_point = (detail::kAsciiZeros & ~std::uint64_t{0xFF00}) | std::uint64_t{'.'} << 8;
    t.bytes = (zero_point & ((std::uint64_t{1} << (8 * prefix)) - 1)) | digits << (8 * prefix);
    t.length = prefix + last + 1;
  }
  return signed_text(t, v);
}

inline char* put_general9(char* out, double v) {
  if (const ShortText t = general9_short(v); t.length >= 0) return put_short(out, t);
  return std::to_chars(out, out + kMaxChars, v, std::chars_format::general, 9).ptr;
}

}  // namespace lptn::fw::csv_number
