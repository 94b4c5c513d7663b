// A pack of L doubles, each lane computed with exactly the arithmetic a double would see: the model
// run for L parameter sets at once (the set scorer of TD3 and the search methods) in the
// processor's vector registers.
//
// Why it gives each lane a double's bits: every operator is the same IEEE operation applied lane
// by lane (GCC's and Clang's vector extensions: +, -, *, / and negation are element-wise and
// correctly rounded, as the scalar ones are), nothing is reassociated, and no fused multiply-add
// is formed (the project builds with -ffp-contract=off on every target, the top CMakeLists.txt
// says why; x86-64's baseline has no FMA anyway). The math functions call std:: per lane.
// Comparisons are left out on purpose: a branch on a value would have to be taken per lane, so
// code that branches on the scalar does not compile for lanes (value_of() has no lane form)
// rather than silently taking lane 0's branch; the LU's pivoting asks SmallLu::lanes_pivot() instead (internal/small_lu.hpp).
//
// Host only (the trainer): the firmware never steps more than one parameter set.
//
// Wider registers: a loop over lanes compiled for x86-64's baseline takes four lanes in two SSE2
// registers; run_on_widest_lanes(f) below compiles f a second time for AVX2 (one register) and
// runs that copy where the processor has AVX2. AVX2 brings no fused multiply-add (that is FMA's
// own flag), so both give the same bits.
#pragma once

#include <cmath>

#include "lptn/scalar.hpp"

namespace lptn {

namespace internal {
// GCC drops a vector_size that depends on a template parameter, so each width is spelled out.
template <int L>
struct LaneVector;
template <>
struct LaneVector<2> {
  typedef double type __attribute__((vector_size(16)));
};
template <>
struct LaneVector<4> {
  typedef double type __attribute__((vector_size(32)));
};
}  // namespace internal

template <int L>
struct Lanes {
  using Vector = typename internal::LaneVector<L>::type;
  static constexpr int kLanes = L;
  Vector v;

  // Uninitialised, as a double is (T x{} is zero): the integrator's stage arrays are made every step.
  Lanes() = default;
  // Every lane x. Not `v = x`: a vector plus a scalar would add to zero, which turns -0.0 into +0.0.
  Lanes(double x) {  // NOLINT(google-explicit-constructor): a constant enters the model as T(c)
    for (int l = 0; l < L; ++l) v[l] = x;
  }
  static Lanes of(const Vector& x) {
    Lanes r;
    r.v = x;
    return r;
  }
  double lane(int l) const { return v[l]; }
  void set_lane(int l, double x) { v[l] = x; }

  Lanes& operator+=(const Lanes& o) { v += o.v; return *this; }
  Lanes& operator-=(const Lanes& o) { v -= o.v; return *this; }
  Lanes& operator*=(const Lanes& o) { v *= o.v; return *this; }
  Lanes& operator/=(const Lanes& o) { v /= o.v; return *this; }
  Lanes operator-() const { return of(-v); }
  friend Lanes operator+(const Lanes& a, const Lanes& b) { return of(a.v + b.v); }
  friend Lanes operator-(const Lanes& a, const Lanes& b) { return of(a.v - b.v); }
  friend Lanes operator*(const Lanes& a, const Lanes& b) { return of(a.v * b.v); }
  friend Lanes operator/(const Lanes& a, const Lanes& b) { return of(a.v / b.v); }
  friend Lanes operator+(const Lanes& a, double b) { return a + Lanes(b); }
  friend Lanes operator-(const Lanes& a, double b) { return a - Lanes(b); }
  friend Lanes operator*(const Lanes& a, double b) { return a * Lanes(b); }
  friend Lanes operator/(const Lanes& a, double b) { return a / Lanes(b); }
  friend Lanes operator+(double a, const Lanes& b) { return Lanes(a) + b; }
  friend Lanes operator-(double a, const Lanes& b) { return Lanes(a) - b; }
  friend Lanes operator*(double a, const Lanes& b) { return Lanes(a) * b; }
  friend Lanes operator/(double a, const Lanes& b) { return Lanes(a) / b; }

  // The model's math functions, found by argument-dependent lookup as the Jets' are.
  template <class F>
  friend Lanes each(const Lanes& a, F f) {
    Lanes r;
    for (int l = 0; l < L; ++l) r.v[l] = f(a.v[l]);
    return r;
  }
  friend Lanes exp(const Lanes& a) { return each(a, [](double x) { return std::exp(x); }); }
  friend Lanes log(const Lanes& a) { return each(a, [](double x) { return std::log(x); }); }
  friend Lanes sqrt(const Lanes& a) { return each(a, [](double x) { return std::sqrt(x); }); }
  friend Lanes abs(const Lanes& a) { return each(a, [](double x) { return std::abs(x); }); }
  friend Lanes pow(const Lanes& a, double b) { return each(a, [b](double x) { return std::pow(x, b); }); }
  friend Lanes pow(double a, const Lanes& b) { return each(b, [a](double x) { return std::pow(a, x); }); }
  friend Lanes pow(const Lanes& a, const Lanes& b) {
    Lanes r;
    for (int l = 0; l < L; ++l) r.v[l] = std::pow(a.v[l], b.v[l]);
    return r;
  }
};

#if defined(__x86_64__) && defined(__GNUC__)
namespace internal {
inline bool has_avx2() {
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return has;
}
// f() with everything it calls inlined into this copy and compiled for AVX2 (flatten), and nothing
// outside it: the out-of-line functions it still calls (libm's pow, say) stay the baseline's. F is
// the caller's own lambda, so no other translation unit makes this instantiation.
template <class F>
[[gnu::target("avx2"), gnu::flatten]] void run_avx2(const F& f) {
  f();
}
}  // namespace internal

// f(), a loop over lanes, in the widest vector registers the processor has: its AVX2 copy where it
// has AVX2, else as built (the baseline's copy left to the compiler's own inlining: flattened too,
// it made the set scorer's batch 6 s longer to compile). The same bits either way.
template <class F>
void run_on_widest_lanes(const F& f) {
  if (internal::has_avx2())
    internal::run_avx2(f);
  else
    f();
}
#else
template <class F>
void run_on_widest_lanes(const F& f) {
  f();
}
#endif

}  // namespace lptn
