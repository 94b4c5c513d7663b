// rotor_speed_convection: rotor cooling that grows with speed.
//
// Physics: the paper scales the conductances to air with the blower's airflow only. A spinning
// rotor also stirs the air in its ducts and at its end rings, so its heat transfer coefficient
// rises with speed even at a fixed airflow:
//     l1r' = l1r (1 + rotor_convection_gain |n| / n_base),  likewise l2r
// Touches the conductances of nodes 3 and 4 to the air (eq. 3, 4).
// Reference: Staton, Cavagnino, "Convection heat transfer and flow calculations suitable for
// electric machines thermal models", IEEE Trans. Ind. Electron. 55(10), 2008.
#pragma once

#include "lptn/effects/effect.hpp"

namespace lptn::effects {

struct RotorSpeedConvection {
  static constexpr std::string_view kName = "rotor_speed_convection";
  static constexpr std::string_view kSummary = "rotor conductances to air grow with speed";
  static constexpr int kExtraStates = 0;
  static constexpr std::string_view kNeeds =
      "rotor telemetry, and speed varying independently of airflow and load (fixed or stepped blower levels)";
  static constexpr HeatSides kSides = HeatSides::rotor;
  static constexpr std::string_view kSignatureLabel = "n/n_base x rotor heat to air, model";
  static constexpr std::string_view kSignatureUnit = "W";
  static constexpr ParamSpec kParams[] = {
      {"rotor_convection_gain", "1", 0.5, 0.0, 5.0, 0.0, "relative rise of rotor-to-air conductance at base speed"},
  };

  template <class T, class R>
  static void adjust(const EffectInputs<R>& e, const T* p, StepConductances<T>& g) {
    const T factor = T(1) + p[0] * e.speed_ratio;
    g.to_air[kRotorWinding] *= factor;
    g.to_air[kRotorCore] *= factor;
  }

  template <class R>
  static R signature(const SignatureInputs<R>& s) {
    const auto g = paper_conductances(s.motor, s.in, s.params);
    const R q = g.to_air[kRotorWinding] * (s.nodes[kRotorWinding] - s.in.ambient_c) +
                g.to_air[kRotorCore] * (s.nodes[kRotorCore] - s.in.ambient_c);
    return s.speed_ratio() * q;
  }
};

}  // namespace lptn::effects
