// windage: friction and windage loss.
//
// Physics: the paper's loss model is electrical only. Bearing friction grows with speed and air
// friction of the rotor and its fan with a higher power of it; one exponent between the two
// (2) describes the sum well over a traction motor's speed range:
//     P_w = windage_base_w (|n| / n_base)^2
// deposited in the rotor core (node 4), where the churned air and the bearings' heat end up.
// Reference: Pyrhonen, Jokinen, Hrabovcova, "Design of Rotating Electrical Machines", 2nd ed.,
// Wiley 2014, sect. 9.5 (mechanical losses).
#pragma once

#include "lptn/effects/effect.hpp"

namespace lptn::effects {

struct Windage {
  static constexpr std::string_view kName = "windage";
  static constexpr std::string_view kSummary = "friction and windage loss ~ speed^2, into the rotor core";
  static constexpr int kExtraStates = 0;
  static constexpr std::string_view kNeeds =
      "rotor telemetry, and speed varying independently of load (coasting at speed, light trains at line speed)";
  static constexpr HeatSides kSides = HeatSides::rotor;
  static constexpr std::string_view kSignatureLabel = "(n/n_base)^2";
  static constexpr std::string_view kSignatureUnit = "1";
  static constexpr ParamSpec kParams[] = {
      {"windage_base_w", "W", 300.0, 1.0, 20000.0, 0.0, "friction and windage loss at base speed"},
  };

  template <class T, class R>
  static void apply(const EffectInputs<R>& e, const T* p, const StepConductances<T>&, HeatBalance<T>& sys,
                    int) {
    sys.heat(kRotorCore, p[0] * (e.speed_ratio * e.speed_ratio));
  }

  template <class R>
  static R signature(const SignatureInputs<R>& s) {
    const R r = s.speed_ratio();
    return r * r;
  }
};

}  // namespace lptn::effects
