// airgap: heat exchange between stator and rotor across the air gap.
//
// Physics: the paper's network has no path between stator and rotor. Across the air gap, heat
// passes by conduction through the thin air layer and by convection in the Taylor-Couette flow
// that the rotor drives, which strengthens with speed. Between the stator core (teeth) and the
// rotor core (surface):
//     l_ag = airgap_lambda (0.25 + 0.75 |n| / n_base)
// a quarter at standstill, the rest growing with speed (a linear stand-in for Nu ~ Re^x).
// Touches nodes 2 and 4. Reference: Boglietti et al., "Evolution and modern approaches for thermal
// analysis of electrical machines", IEEE Trans. Ind. Electron. 56(3), 2009 (air-gap convection).
#pragma once

#include "lptn/effects/effect.hpp"

namespace lptn::effects {

struct Airgap {
  static constexpr std::string_view kName = "airgap";
  static constexpr std::string_view kSummary =
      "stator core <-> rotor core across the air gap, growing with speed";
  static constexpr int kExtraStates = 0;
  static constexpr std::string_view kNeeds =
      "rotor telemetry, and stator and rotor temperatures moving apart (hard acceleration after a soak, or "
      "cycles where rotor and stator losses differ)";
  static constexpr HeatSides kSides = HeatSides::both;
  // The conductance's own size is what a fit finds.
  static constexpr std::string_view kSignatureLabel = "(0.25 + 0.75 n/n_base)(T2 - T4), model";
  static constexpr std::string_view kSignatureUnit = "K";
  static constexpr ParamSpec kParams[] = {
      {"airgap_lambda", "W/K", 50.0, 1.0, 3000.0, 0.0, "air-gap conductance at base speed"},
  };

  template <class T, class R>
  static void apply(const EffectInputs<R>& e, const T* p, const StepConductances<T>&, HeatBalance<T>& sys,
                    int) {
    sys.path(kStatorCore, kRotorCore, p[0] * (R(0.25) + R(0.75) * e.speed_ratio));
  }

  template <class R>
  static R signature(const SignatureInputs<R>& s) {
    return (R(0.25) + R(0.75) * s.speed_ratio()) * (s.nodes[kStatorCore] - s.nodes[kRotorCore]);
  }
};

}  // namespace lptn::effects
