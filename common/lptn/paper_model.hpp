// The paper's model, equations 1-14, in one place: the loss model and the four-node network.
//
//   Nodes: 1 stator winding, 2 stator core, 3 rotor winding (cage), 4 rotor core.
//
//   (1) C1 dT1/dt = P1 - l1s (T1 - Tenv) - l12s (T1 - T2)
//   (2) C2 dT2/dt = P2 - l2s (T2 - Tenv) - l12s (T2 - T1)
//   (3) C3 dT3/dt = P3 - l1r (T3 - Tenv) - l12r (T3 - T4)
//   (4) C4 dT4/dt = P4 - l2r (T4 - Tenv) - l12r (T4 - T3)
//   (5) P1 = Kstemp Pcu1 + Kstray Pstray + Kharm Pharm         P2 = KPfe Pfe
//   (6) P3 = Krtemp Pcu2 + (1-Kstray) Pstray + (1-Kharm) Pharm P4 = (1-KPfe) Pfe
//   (7) Pcu1 = 3 R1(T1) I1^2
//   (8) R1(T) = R1,20 (1 + aR1 (T - 20))
//   (9) I21 from I1 and the magnetizing current at the present flux: I21^2 = I1^2 - Im^2
//  (10) Pcu2 = 3 R21(T3) I21^2, or with torque on the bus the slip power T 2pi (f - p n/60) / p
//  (11) Pstray = PSUP (f/fnom)^1.5 (I1/I1,nom)^2
//  (12) Pfe = Kf f^a Bmax^b, Bmax ~ V/f; written here relative to the rated point:
//       Pfe = Pfe,rated (f/fnom)^a (psi)^b with psi = (V/f) / (Vnom/fnom) the flux ratio
//  (13) Pharm = table over f, zero while the converter's pulses are off
//  (14) l = l_nom (Vdot / Vdot_nom)^0.8 for the four conductances to the cooling air
//
// Losses depend only on inputs and motor constants (type R); the conductances and loss-split
// factors are parameters (type T, possibly a Jet). Temperature-dependent copper losses enter the
// network as affine terms so that the integrator treats them implicitly.
#pragma once

#include "lptn/heat_balance.hpp"
#include "lptn/inputs.hpp"
#include "lptn/motor_constants.hpp"
#include "lptn/params.hpp"

namespace lptn {

// The paper's calibratable parameters: the first entries of every parameter vector.
enum PaperParam : int {
  kLambda1s,
  kLambda2s,
  kLambda12s,
  kLambda1r,
  kLambda2r,
  kLambda12r,
  kKStemp,
  kKRtemp,
  kKStray,
  kKHarm,
  kKPfe,
  kNumPaperParams
};

// The conductances to the cooling air: what a motor's cooling factor scales (a clogged filter, a
// weaker blower, a fleet's scatter), in the synthetic plant, the fleet calibration and its tests.
inline constexpr int kConductancesToAir[] = {kLambda1s, kLambda2s, kLambda1r, kLambda2r};

inline constexpr ParamSpec kPaperParams[kNumPaperParams] = {
    {"lambda_1s", "W/K", 40.0, 1.0, 1000.0, 40.0, "stator winding to cooling air, at nominal airflow"},
    {"lambda_2s", "W/K", 100.0, 1.0, 2000.0, 100.0, "stator core to cooling air, at nominal airflow"},
    {"lambda_12s", "W/K", 150.0, 1.0, 5000.0, 150.0, "stator winding to stator core"},
    {"lambda_1r", "W/K", 40.0, 1.0, 1000.0, 40.0, "rotor winding to cooling air, at nominal airflow"},
    {"lambda_2r", "W/K", 60.0, 1.0, 2000.0, 60.0, "rotor core to cooling air, at nominal airflow"},
    {"lambda_12r", "W/K", 200.0, 1.0, 5000.0, 200.0, "rotor winding to rotor core"},
    {"k_stemp", "1", 1.0, 0.5, 2.0, 1.0, "factor on the stator copper loss (eq. 5)"},
    {"k_rtemp", "1", 1.0, 0.5, 2.0, 1.0, "factor on the rotor copper loss (eq. 6)"},
    {"k_stray", "1", 0.6, 0.0, 1.0, 0.6, "share of the stray loss in the stator winding (eq. 5)"},
    {"k_harm", "1", 0.5, 0.0, 1.0, 0.5, "share of the harmonic loss in the stator winding (eq. 5)"},
    {"k_pfe", "1", 0.85, 0.0, 1.0, 0.85, "share of the iron loss in the stator core (eq. 5)"},
};

// Which way the rotor copper loss was found this step (the observer reports it).
enum class RotorLossRoute : unsigned char { slip_power, rotor_current };

// Below this share of rated current the converter's pulses are taken to be off: no flux, no iron,
// stray or harmonic loss.
inline constexpr double kPulsesOffCurrentShare = 0.01;
// Flux from V/f is meaningless near standstill (V -> IR drop only); below this frequency the
// nominal profile is used instead.
inline constexpr double kMinFluxFrequencyHz = 1.0;
inline constexpr double kMaxFluxRatio = 1.3;

template <class R>
struct OperatingLosses {
  R stator_copper_20c_w = R(0);  // eq. 7 with R1,20: scaled by (1 + aR1 (T1 - 20)) in the network
  R rotor_copper_w = R(0);       // eq. 10, slip-power route (independent of temperature)
  R rotor_copper_20c_w = R(0);   // eq. 10, rotor-current route at 20 C (scaled with T3)
  R stray_w = R(0);              // eq. 11
  R iron_w = R(0);               // eq. 12
  R harmonic_w = R(0);           // eq. 13
  R flux_ratio = R(0);           // psi: present flux over rated flux
  RotorLossRoute rotor_route = RotorLossRoute::rotor_current;
  bool pulses_on = false;
};

// Linear interpolation in the harmonic-loss table, held constant beyond its ends.
template <class R>
R harmonic_loss(const MotorConstants<R>& m, R frequency_hz) {
  const int n = m.harmonic_points;
  if (n <= 0) return R(0);
  if (frequency_hz <= m.harmonic_frequency_hz[0]) return m.harmonic_loss_w[0];
  for (int i = 1; i < n; ++i) {
    if (frequency_hz <= m.harmonic_frequency_hz[i]) {
      const R f0 = m.harmonic_frequency_hz[i - 1];
      const R f1 = m.harmonic_frequency_hz[i];
      const R s = (frequency_hz - f0) / (f1 - f0);
      return m.harmonic_loss_w[i - 1] + s * (m.harmonic_loss_w[i] - m.harmonic_loss_w[i - 1]);
    }
  }
  return m.harmonic_loss_w[n - 1];
}

// The flux ratio psi. From V/f where voltage is on the bus; otherwise the nominal profile: rated
// flux up to rated frequency, field weakening (psi = fnom/f) above it.
template <class R>
R flux_ratio(const MotorConstants<R>& m, const Inputs<R>& in) {
  using std::abs;
  const R f = abs(in.frequency_hz);
  if (in.has_voltage && f > R(kMinFluxFrequencyHz)) {
    const R psi = (in.voltage_v / f) / (m.rated_voltage_v / m.rated_frequency_hz);
    return psi < R(0) ? R(0) : (psi > R(kMaxFluxRatio) ? R(kMaxFluxRatio) : psi);
  }
  return f <= m.rated_frequency_hz ? R(1) : m.rated_frequency_hz / f;
}

// Equations 7-13 for one step's inputs.
template <class R>
OperatingLosses<R> operating_losses(const MotorConstants<R>& m, const Inputs<R>& in) {
  using std::abs;
  using std::pow;
  OperatingLosses<R> l;
  const R i1 = abs(in.current_a);
  const R f = abs(in.frequency_hz);
  l.pulses_on = i1 > R(kPulsesOffCurrentShare) * m.rated_current_a;
  l.stator_copper_20c_w = R(3) * m.stator_resistance_20c_ohm * i1 * i1;  // eq. 7, 8
  if (!l.pulses_on) {
    l.rotor_route = in.has_torque ? RotorLossRoute::slip_power : RotorLossRoute::rotor_current;
    return l;  // no flux, no slip, no switching: only the (tiny) copper loss of any residual current
  }
  l.flux_ratio = flux_ratio(m, in);
  if (in.has_torque) {  // eq. 10 from the slip power: T * slip angular frequency / p
    constexpr R kTwoPi = R(6.283185307179586);
    const R p = R(m.pole_pairs);
    const R slip_w = in.torque_nm * kTwoPi * (in.frequency_hz - p * in.speed_rpm / R(60)) / p;
    l.rotor_copper_w = slip_w > R(0) ? slip_w : R(0);
    l.rotor_route = RotorLossRoute::slip_power;
  } else {  // eq. 9, 10 from the rotor current
    const R im = m.magnetizing_current_a * l.flux_ratio;
    const R i21_sq = i1 * i1 - im * im;
    l.rotor_copper_20c_w = i21_sq > R(0) ? R(3) * m.rotor_resistance_20c_ohm * i21_sq : R(0);
    l.rotor_route = RotorLossRoute::rotor_current;
  }
  const R f_rel = f / m.rated_frequency_hz;
  const R i_rel = i1 / m.rated_current_a;
  l.stray_w = m.stray_rated_w * pow(f_rel, R(1.5)) * i_rel * i_rel;                           // eq. 11
  l.iron_w = m.iron_rated_w * pow(f_rel, m.iron_alpha) * pow(l.flux_ratio, m.iron_beta);     // eq. 12
  l.harmonic_w = harmonic_loss(m, f);                                                          // eq. 13
  return l;
}

// The airflow that cools: the blower's, but never below the natural-convection floor.
template <class R>
R effective_airflow(const MotorConstants<R>& m, R airflow_m3s) {
  const R floor = m.min_airflow_fraction * m.nominal_airflow_m3s;
  return airflow_m3s < floor ? floor : airflow_m3s;
}

// Eq. 14: how much the conductances to the air grow or shrink with the cooling airflow.
template <class R>
R airflow_factor(const MotorConstants<R>& m, R airflow_m3s) {
  using std::pow;
  return pow(effective_airflow(m, airflow_m3s) / m.nominal_airflow_m3s, m.airflow_exponent);
}

// Conductances of one step (W/K): those to the air already scaled with airflow (eq. 14).
// Effects may adjust them before the network is assembled.
template <class T>
struct StepConductances {
  T to_air[kNumNodes]{};  // l1s, l2s, l1r, l2r, indexed by node
  T stator_internal{};    // l12s
  T rotor_internal{};     // l12r
};

// k: airflow_factor() at the step's airflow.
template <class T, class R>
StepConductances<T> paper_conductances(const R& k, const T* p) {
  StepConductances<T> g;
  g.to_air[kStatorWinding] = p[kLambda1s] * k;
  g.to_air[kStatorCore] = p[kLambda2s] * k;
  g.to_air[kRotorWinding] = p[kLambda1r] * k;
  g.to_air[kRotorCore] = p[kLambda2r] * k;
  g.stator_internal = p[kLambda12s];
  g.rotor_internal = p[kLambda12r];
  return g;
}
template <class T, class R>
StepConductances<T> paper_conductances(const MotorConstants<R>& m, const Inputs<R>& in, const T* p) {
  return paper_conductances(airflow_factor(m, in.airflow_m3s), p);
}

// Equations 1-6 into the step's linear system.
template <class T, class R>
void assemble_paper_network(const MotorConstants<R>& m, const Inputs<R>& in, const OperatingLosses<R>& l,
                            const StepConductances<T>& g, const T* p, HeatBalance<T>& sys) {
  for (int i = 0; i < kNumNodes; ++i) {
    sys.capacitance[i] = T(m.capacitance_j_per_k[i]);
    sys.to_fixed(i, g.to_air[i], in.ambient_c);
  }
  sys.path(kStatorWinding, kStatorCore, g.stator_internal);
  sys.path(kRotorWinding, kRotorCore, g.rotor_internal);

  // eq. 5: stator winding and stator core
  sys.heat_affine(kStatorWinding, p[kKStemp] * l.stator_copper_20c_w, m.stator_resistance_alpha_per_k);
  sys.heat(kStatorWinding, p[kKStray] * l.stray_w + p[kKHarm] * l.harmonic_w);
  sys.heat(kStatorCore, p[kKPfe] * l.iron_w);
  // eq. 6: rotor winding and rotor core
  if (l.rotor_route == RotorLossRoute::slip_power) {
    sys.heat(kRotorWinding, p[kKRtemp] * l.rotor_copper_w);
  } else {
    sys.heat_affine(kRotorWinding, p[kKRtemp] * l.rotor_copper_20c_w, m.rotor_resistance_alpha_per_k);
  }
  sys.heat(kRotorWinding, (T(1) - p[kKStray]) * l.stray_w + (T(1) - p[kKHarm]) * l.harmonic_w);
  sys.heat(kRotorCore, (T(1) - p[kKPfe]) * l.iron_w);
}

}  // namespace lptn
