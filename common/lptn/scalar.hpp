// Scalar helpers shared by every model header.
//
// The model is templated on the scalar so that one source runs in float on the drive controller,
// in double in the trainer and with ceres::Jet for exact derivatives. Math functions are called
// unqualified after `using std::xxx;` so that argument-dependent lookup finds the Jet overloads;
// nothing here includes Ceres.
#pragma once

#include <cmath>
#include <type_traits>

namespace lptn {

// The plain number behind a scalar: the value itself for float/double, the `.a` part of a Jet.
// Used only for decisions (pivoting, clamping branches), never inside a derivative path.
template <class T>
constexpr double value_of(const T& x) {
  if constexpr (requires { x.a; }) {
    return static_cast<double>(x.a);
  } else {
    return static_cast<double>(x);
  }
}

// Whether T is a pack of lanes (lanes.hpp): several doubles stepped at once, each with a double's
// arithmetic. Decisions on a value (pivoting) are then taken per lane.
template <class T>
inline constexpr bool kIsLanes = requires { T::kLanes; };

// x held within [lo, hi] (NaN passes); lanes each on their own.
template <class T>
constexpr T clamp_value(const T& x, double lo, double hi) {
  if constexpr (kIsLanes<T>) {
    T r = x;
    for (int l = 0; l < T::kLanes; ++l) r.set_lane(l, clamp_value(x.lane(l), lo, hi));
    return r;
  } else {
    if (value_of(x) < lo) return T(lo);
    if (value_of(x) > hi) return T(hi);
    return x;
  }
}

}  // namespace lptn
