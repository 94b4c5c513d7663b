// Exact range arithmetic on DBC numbers with GMP's rationals: a number of up to 300 digits with an
// exponent up to 300 is a fraction of two big integers, as Python's Fraction held it before.
#include "can/dbc/internal/exact.hpp"

#include <gmp.h>

#include <cstdio>
#include <cstdlib>

namespace lptn::dbc::internal {

// RAII for mpq_t/mpz_t: the C API, so only libgmp is linked.
struct Q {
  mpq_t v;
  Q() { mpq_init(v); }
  ~Q() { mpq_clear(v); }
  Q(const Q&) = delete;
  Q& operator=(const Q&) = delete;
};
struct Z {
  mpz_t v;
  Z() { mpz_init(v); }
  ~Z() { mpz_clear(v); }
  Z(const Z&) = delete;
  Z& operator=(const Z&) = delete;
};

// "-12.5e-3" -> -125/10000, exactly. The tokenizer has checked the shape.
void set_decimal(mpq_t out, const std::string& text) {
  std::string digits;
  long exponent = 0;
  bool negative = false;
  std::size_t i = 0;
  if (i < text.size() && (text[i] == '-' || text[i] == '+')) negative = text[i++] == '-';
  bool fraction = false;
  for (; i < text.size() && text[i] != 'e' && text[i] != 'E'; ++i) {
    if (text[i] == '.') {
      fraction = true;
      continue;
    }
    digits += text[i];
    if (fraction) --exponent;
  }
  if (i < text.size()) exponent += std::strtol(text.c_str() + i + 1, nullptr, 10);
  if (digits.empty()) digits.push_back('0');  // not = "0": GCC 12 warns there (-Wrestrict, PR 105329)
  Z n, p;
  mpz_set_str(n.v, digits.c_str(), 10);
  mpz_ui_pow_ui(p.v, 10, static_cast<unsigned long>(exponent < 0 ? -exponent : exponent));
  if (exponent >= 0) {
    mpz_mul(n.v, n.v, p.v);
    mpz_set_ui(p.v, 1);
  }
  if (negative) mpz_neg(n.v, n.v);
  mpq_set_num(out, n.v);
  mpq_set_den(out, p.v);
  mpq_canonicalize(out);
}

namespace {

// An integer's digits, else %g of the nearest double (Python's f"{float(value):g}").
std::string format(const mpq_t q) {
  if (mpz_cmp_ui(mpq_denref(q), 1) == 0) {
    char* s = mpz_get_str(nullptr, 10, mpq_numref(q));
    std::string out(s);
    void (*release)(void*, std::size_t);
    mp_get_memory_functions(nullptr, nullptr, &release);
    release(s, out.size() + 1);
    return out;
  }
  // 40 significant digits, then strtod: the double nearest the exact value.
  mpf_t f;
  mpf_init2(f, 256);
  mpf_set_q(f, q);
  char buf[128];
  gmp_snprintf(buf, sizeof buf, "%.40Fe", f);
  mpf_clear(f);
  char out[64];
  std::snprintf(out, sizeof out, "%g", std::strtod(buf, nullptr));
  return out;
}

// The whole number, clamped to +-2^64 (what a long double holds exactly).
long double clamped(const mpz_t z) {
  Z limit;
  mpz_ui_pow_ui(limit.v, 2, 64);
  if (mpz_cmp(z, limit.v) >= 0) return 18446744073709551616.0L;
  mpz_neg(limit.v, limit.v);
  if (mpz_cmp(z, limit.v) <= 0) return -18446744073709551616.0L;
  const bool negative = mpz_sgn(z) < 0;
  Z a;
  mpz_abs(a.v, z);
  // Two 32-bit halves: mpz_get_ui is 64 bits wide on LP64 hosts, but say so without assuming it.
  Z hi;
  mpz_tdiv_q_2exp(hi.v, a.v, 32);
  const long double value = static_cast<long double>(mpz_get_ui(hi.v)) * 4294967296.0L +
                            static_cast<long double>(mpz_fdiv_ui(a.v, 4294967296UL));
  return negative ? -value : value;
}

void set_ld(mpq_t out, long double whole) {
  // Whole numbers below 2^64 in magnitude: the decimal text is exact.
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.0Lf", whole);
  set_decimal(out, buf);
}

}  // namespace

ExactRange exact_range(const Number& factor, const Number& offset, const Number& minimum, const Number& maximum,
                       long double raw_low, long double raw_high) {
  ExactRange r;
  Q f, o, mn, mx, a, b, lo, hi;
  set_decimal(f.v, factor.text);
  set_decimal(o.v, offset.text);
  set_decimal(mn.v, minimum.text);
  set_decimal(mx.v, maximum.text);
  if (mpq_cmp(mn.v, mx.v) > 0) {
    r.min_above_max = true;
    return r;
  }
  if (mpq_sgn(mn.v) == 0 && mpq_sgn(mx.v) == 0) {
    r.no_range = true;
    return r;
  }
  mpq_sub(a.v, mn.v, o.v);
  mpq_div(a.v, a.v, f.v);
  mpq_sub(b.v, mx.v, o.v);
  mpq_div(b.v, b.v, f.v);
  if (mpq_cmp(a.v, b.v) > 0) mpq_swap(a.v, b.v);
  r.low_text = format(a.v);
  r.high_text = format(b.v);
  set_ld(lo.v, raw_low);
  set_ld(hi.v, raw_high);
  r.exceeds_bits = mpq_cmp(a.v, lo.v) < 0 || mpq_cmp(b.v, hi.v) > 0;
  Z c, fl, l, h;
  mpz_cdiv_q(c.v, mpq_numref(a.v), mpq_denref(a.v));
  mpz_fdiv_q(fl.v, mpq_numref(b.v), mpq_denref(b.v));
  mpz_set(l.v, mpq_numref(lo.v));
  mpz_set(h.v, mpq_numref(hi.v));
  r.holds_no_value = mpz_cmp(c.v, fl.v) > 0 || mpz_cmp(c.v, h.v) > 0 || mpz_cmp(fl.v, l.v) < 0;
  r.low = clamped(c.v);
  r.high = clamped(fl.v);
  return r;
}

}  // namespace lptn::dbc::internal

namespace lptn::dbc {

int compare_exact(const std::string& number, long long value) {
  internal::Q q, v;
  internal::set_decimal(q.v, number);
  mpq_set_si(v.v, value, 1);
  const int c = mpq_cmp(q.v, v.v);
  return c < 0 ? -1 : c > 0 ? 1 : 0;
}

}  // namespace lptn::dbc
