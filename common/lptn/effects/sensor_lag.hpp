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
};

}  // namespace lptn::effects
