// sensor_lag: the stator winding sensor lags its node.
//
// Physics: the paper takes the sensor to read node 1 exactly. A PT100 or thermocouple sits in the
// slot between insulation layers and reads the winding through a thermal resistance and its own
// heat capacity: a first-order lag
//     tau dTs/dt = T1 - Ts
// Adds one state (Ts); the stator winding sensor then reads Ts instead of T1. At the start of a
// cycle Ts = T1. Reference: Wallscheid, "Thermal monitoring of electric motors: state-of-the-art
// review and future challenges", IEEE Open J. Ind. Appl. 2, 2021 (sensor placement and dynamics).
#pragma once

#include "lptn/effects/effect.hpp"

namespace lptn::effects {

struct SensorLag {
  static constexpr std::string_view kName = "sensor_lag";
  static constexpr std::string_view kSummary = "first-order lag of the stator winding sensor";
  static constexpr int kExtraStates = 1;
  static constexpr std::string_view kNeeds =
      "fast load steps (hard acceleration or braking from a steady state), logged at 1 Hz or faster";
  static constexpr HeatSides kSides = HeatSides::stator;
  // Its neutral tau = 0 is singular (1/tau in the model). Its limit is Ts = T1 - tau dT1/dt, so the
  // score at a small tau (1 ms, below every sensor's and far below the 0.1 s step) is the score at
  // the limit: the sensitivity -dT1/dt.
  static constexpr double kScoreAt = 1e-3;
  // A lagging sensor reads T1 - tau dT1/dt.
  static constexpr std::string_view kSignatureLabel = "dT1/dt, model";
  static constexpr std::string_view kSignatureUnit = "K/s";
  static constexpr ParamSpec kParams[] = {
      {"sensor_time_constant_s", "s", 30.0, 0.5, 1000.0, 0.0, "time constant of the stator sensor"},
  };

  static void layout(StateLayout& s, int first_state) { s.stator_sensor_state = first_state; }

  template <class T, class R>
  static void apply(const EffectInputs<R>&, const T* p, const StepConductances<T>&, HeatBalance<T>& sys,
                    int first_state) {
    const T rate = T(1) / p[0];
    sys.coupling(first_state, kStatorWinding, rate);
    sys.coupling(first_state, first_state, -rate);
  }

  template <class T>
  static void initialize(T* x, int first_state) {
    x[first_state] = x[kStatorWinding];
  }

  template <class R>
  static R signature(const SignatureInputs<R>& s) {
    return s.winding_rate_k_per_s;
  }
};

}  // namespace lptn::effects
