// Parameter descriptions and the normalized coordinates calibrators work in.
#pragma once

#include <string_view>

#include "lptn/scalar.hpp"

namespace lptn {

// One model parameter: its name in motor files and calibration results, unit, default value and
// bounds. `neutral` is the value at which an effect's contribution vanishes (diagnostics test an
// effect's score there); for the paper's own parameters it equals `initial`.
struct ParamSpec {
  std::string_view name;
  std::string_view unit;
  double initial;
  double min;
  double max;
  double neutral;
  std::string_view description;
};

// Conductances and time constants span decades, so calibrators search them on a log scale; a
// parameter whose lower bound is not positive (a fraction that may be zero) uses a linear scale.
constexpr bool uses_log_scale(double min, double max) { return min > 0.0 && max > min; }

// Maps a value in [min, max] onto u in [-1, 1] (the range of an actor's tanh output).
template <class T>
T to_normalized(const T& value, double min, double max) {
  using std::log;
  if (uses_log_scale(min, max)) {
    return (log(value) - log(min)) / (log(max) - log(min)) * 2.0 - 1.0;
  }
  return (value - min) / (max - min) * 2.0 - 1.0;
}

// The inverse of to_normalized: u in [-1, 1] onto [min, max].
template <class T>
T from_normalized(const T& u, double min, double max) {
  using std::exp;
  using std::log;
  const T s = (u + 1.0) * 0.5;
  if (uses_log_scale(min, max)) {
    return exp(log(min) + s * (log(max) - log(min)));
  }
  return min + s * (max - min);
}

}  // namespace lptn
