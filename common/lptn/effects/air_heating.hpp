// air_heating: the cooling air is warmed by the stator before it reaches the rotor.
//
// Physics: the paper uses one air temperature for all nodes. In a forced-ventilated motor the air
// that cools the rotor has passed (part of) the stator first and carries some of its heat:
//     T_air,rotor = T_amb + air_heating_fraction * Q_stator / (rho c_p Vdot)
//     Q_stator = l1s (T1 - T_amb) + l2s (T2 - T_amb)
// with rho c_p = 1206 J/(m^3 K) for air near 20 C. The rotor's conductances to air (eq. 3, 4) see
// T_air,rotor instead of T_amb: a one-way coupling from the stator nodes into the rotor nodes.
// The warming is largest at low airflow and high load, so it is distinguishable from weaker rotor
// cooling only where airflow does not move with load (cycles with fixed blower levels).
// Reference: Boglietti et al., IEEE Trans. Ind. Electron. 56(3), 2009 (air-flow network).
#pragma once

#include "lptn/effects/effect.hpp"

namespace lptn::effects {

struct AirHeating {
  static constexpr std::string_view kName = "air_heating";
  static constexpr std::string_view kSummary = "rotor cooling air pre-warmed by the stator's heat";
  static constexpr int kExtraStates = 0;
  static constexpr std::string_view kNeeds = "cycles at fixed blower levels (airflow not moving with load), with rotor telemetry";
  static constexpr HeatSides kSides = HeatSides::both;
  // The rotor's air warmed by Q_stator / (rho c_p Vdot), Q_stator through the stator's conductances to air.
  static constexpr std::string_view kSignatureLabel = "Q_stator / (rho c_p Vdot), model";
  static constexpr std::string_view kSignatureUnit = "K";
  static constexpr ParamSpec kParams[] = {
      {"air_heating_fraction", "1", 0.5, 0.0, 1.0, 0.0, "share of the stator's heat carried to the rotor's air"},
  };
  static constexpr double kAirVolumetricHeatJPerM3K = 1206.0;

  template <class T, class R>
  static void apply(const EffectInputs<R>& e, const T* p, const StepConductances<T>& g, HeatBalance<T>& sys,
                    int) {
    // dT_air = k (l1s (T1 - Ta) + l2s (T2 - Ta)), k in K/W
    const T k = p[0] / R(kAirVolumetricHeatJPerM3K * e.effective_airflow_m3s);
    const R ta = e.in.ambient_c;
    for (int r : {kRotorWinding, kRotorCore}) {
      const T gk = g.to_air[r] * k;
      sys.coupling(r, kStatorWinding, gk * g.to_air[kStatorWinding]);
      sys.coupling(r, kStatorCore, gk * g.to_air[kStatorCore]);
      sys.heat(r, -gk * (g.to_air[kStatorWinding] + g.to_air[kStatorCore]) * ta);
    }
  }

  template <class R>
  static R signature(const SignatureInputs<R>& s) {
    const auto g = paper_conductances(s.motor, s.in, s.params);
    const R q = g.to_air[kStatorWinding] * (s.nodes[kStatorWinding] - s.in.ambient_c) +
                g.to_air[kStatorCore] * (s.nodes[kStatorCore] - s.in.ambient_c);
    return q / (R(kAirVolumetricHeatJPerM3K) * effective_airflow(s.motor, s.in.airflow_m3s));
  }
};

}  // namespace lptn::effects
