// The dictionary: generic terms for physics nobody wrote into the library.
//
// A real motor's missing physics is rarely one of the library's named effects. Diagnose then tries
// these (PySINDy's shape: a dictionary of candidate terms, sparse selection, each readable as
// physics). Every term is an effect like any other: a calibration enables it by name, the exported
// header and the firmware carry it, and it does nothing at its neutral value. Three families:
//
//   heat_<node>_<form>         extra heat into one node, P_r * shape(operating point), with P_r its
//                              size at the rated point and the shape's exponent k free:
//                                i2f    (I/I_r)^2 (f/f_r)^k   current-and-frequency losses (AC copper,
//                                                             eddy currents in the conductors)
//                                fluxf  psi^2 (f/f_r)^k       flux-and-frequency losses (iron-like)
//                                speed  (n/n_b)^k             mechanical losses (bearings, windage)
//                                power  (P/P_r)^k             losses following the shaft power
//                              and, for sources that switch on (a modulation pattern changing, a
//                              cooling duct's resonance), P_r times a step at a fitted threshold x:
//                                above_f  s((f/f_r - x)/w)    above a frequency
//                                above_i  s((I/I_r - x)/w)    above a current
//                              s the logistic, w = 0.03 (2 Hz at a 65 Hz rating): a smooth step, so
//                              that LM can move the threshold. No speed threshold: speed is
//                              frequency over the pole pairs to within the slip, and the two
//                              would be twins the data cannot tell apart.
//   cooling_<side>_speed       the side's conductances to air times 1 + a (n/n_b)^k (a fan or
//                              rotor stirring the air, beyond eq. 14's airflow)
//   airflow_<side>_exponent    the side's conductances to air times (V/V_n)^d: eq. 14's exponent
//                              0.8 changed by d (another flow regime)
//                              <side> is stator, rotor or both: a change of the cooling air itself
//                              (warm exhaust air drawn back in at low airflow, a duct that chokes)
//                              acts on both sides at once, and one term then explains both sensors
//   path_<node>_<node>         a conductance between two nodes the paper leaves unconnected
//   mass_<node>                a fifth thermal mass behind the node (a frame or housing behind the
//                              stator core, a shaft behind the rotor core, end-winding air behind the
//                              stator winding): its conductance to the node, its capacity and its own
//                              conductance to the cooling air (scaled with airflow as eq. 14 scales
//                              the paper's); the slow mode four nodes cannot make. Three, not four:
//                              with sensor_lag and all three, the states fill kMaxStates.
//
// Terms are appended to the library's list (effects/library.hpp) as one group, after the named
// effects, so that every existing parameter keeps its index.
#pragma once

#include <array>
#include <cmath>
#include <initializer_list>
#include <string_view>

#include "lptn/effects/effect.hpp"
#include "lptn/effects/effect_list.hpp"

namespace lptn::terms {

inline constexpr std::string_view kNodeIds[kNumNodes] = {"stator_winding", "stator_core", "rotor_winding", "rotor_core"};
inline constexpr std::string_view kNodeWords[kNumNodes] = {"stator winding", "stator core", "rotor winding",
                                                          "rotor core"};

// A name built at compile time from parts (the terms' names and their parameters' names).
struct FixedText {
  char text[96]{};
  std::size_t size = 0;
  constexpr std::string_view view() const { return {text, size}; }
};
constexpr FixedText join(std::initializer_list<std::string_view> parts) {
  FixedText out;
  for (std::string_view part : parts)
    for (char c : part) out.text[out.size++] = c;
  return out;
}

// Ratios below this are taken as this: x^k then stays finite in value and derivative (log x) for
// every exponent the bounds allow, in float too.
inline constexpr double kTinyRatio = 1e-6;

template <class R>
R at_least_tiny(R x) {
  return x < R(kTinyRatio) ? R(kTinyRatio) : x;
}

namespace forms {

struct CurrentFrequency {
  static constexpr std::string_view kId = "i2f";
  static constexpr std::string_view kFormula = "P_r (I/I_r)^2 (f/f_r)^k";
  static constexpr std::string_view kWords = "growing as I^2 f^k";
  static constexpr double kExponent[3] = {1.0, 0.0, 3.0};  // initial (and neutral), min, max
  template <class T, class R>
  static T shape(const EffectInputs<R>& e, const T& k) {
    using std::abs;
    using std::pow;
    const R i = abs(e.in.current_a) / e.motor.rated_current_a;
    return i * i * pow(at_least_tiny(abs(e.in.frequency_hz) / e.motor.rated_frequency_hz), k);
  }
};

struct FluxFrequency {
  static constexpr std::string_view kId = "fluxf";
  static constexpr std::string_view kFormula = "P_r psi^2 (f/f_r)^k";
  static constexpr std::string_view kWords = "growing as psi^2 f^k (while the pulses are on)";
  static constexpr double kExponent[3] = {1.5, 0.5, 3.0};
  template <class T, class R>
  static T shape(const EffectInputs<R>& e, const T& k) {
    using std::abs;
    using std::pow;
    if (!e.losses.pulses_on) return T(0);
    const R psi = e.losses.flux_ratio;
    return psi * psi * pow(at_least_tiny(abs(e.in.frequency_hz) / e.motor.rated_frequency_hz), k);
  }
};

struct Speed {
  static constexpr std::string_view kId = "speed";
  static constexpr std::string_view kFormula = "P_r (n/n_b)^k";
  static constexpr std::string_view kWords = "growing as speed^k";
  static constexpr double kExponent[3] = {2.0, 0.5, 4.0};
  template <class T, class R>
  static T shape(const EffectInputs<R>& e, const T& k) {
    using std::pow;
    return pow(at_least_tiny(e.speed_ratio), k);
  }
};

// A smooth step at threshold x of the ratio r: 0 well below, 1 well above, 1/2 at x.
inline constexpr double kStepWidth = 0.03;
template <class T, class R>
T smooth_step(R ratio, const T& threshold) {
  using std::exp;
  T z = (T(ratio) - threshold) / T(kStepWidth);
  // Beyond +-40 widths the step is 0 or 1 to double precision; the clamp keeps exp finite (float too).
  z = clamp_value(z, -40.0, 40.0);
  return T(1) / (T(1) + exp(-z));
}

// Heat that switches on above a threshold x of one input's ratio to its rating: one template, the
// quantity (frequency, current) giving its name, its id in the term's name, its variable in the
// formula and its ratio.
template <class Quantity>
struct Threshold {
  static constexpr FixedText kIdText = join({"above_", Quantity::kSymbol});
  static constexpr FixedText kFormulaText = join({"P_r s((", Quantity::kVariable, "/", Quantity::kVariable, "_r - x)/0.03)"});
  static constexpr FixedText kWordsText = join({"switching on above a ", Quantity::kName});
  static constexpr FixedText kSecondDescriptionText =
      join({"the ", Quantity::kName, " it switches on above, as a share of the rated ", Quantity::kName});
  static constexpr FixedText kThresholdWordsText = join({" of the rated ", Quantity::kName, ", "});
  static constexpr std::string_view kId = kIdText.view();
  static constexpr std::string_view kFormula = kFormulaText.view();
  static constexpr std::string_view kWords = kWordsText.view();
  static constexpr std::string_view kSecondId = "threshold";
  static constexpr std::string_view kSecondDescription = kSecondDescriptionText.view();
  static constexpr std::string_view kThresholdWords = kThresholdWordsText.view();
  static constexpr double kExponent[3] = {0.5, 0.05, 2.0};  // the threshold: initial (and neutral), min, max
  template <class T, class R>
  static T shape(const EffectInputs<R>& e, const T& x) {
    return smooth_step<T, R>(Quantity::ratio(e), x);
  }
};

struct Frequency {
  static constexpr std::string_view kName = "frequency";
  static constexpr std::string_view kSymbol = "f";
  static constexpr std::string_view kVariable = "f";
  template <class R>
  static R ratio(const EffectInputs<R>& e) {
    using std::abs;
    return abs(e.in.frequency_hz) / e.motor.rated_frequency_hz;
  }
};

struct Current {
  static constexpr std::string_view kName = "current";
  static constexpr std::string_view kSymbol = "i";
  static constexpr std::string_view kVariable = "I";
  template <class R>
  static R ratio(const EffectInputs<R>& e) {
    using std::abs;
    return abs(e.in.current_a) / e.motor.rated_current_a;
  }
};

using FrequencyThreshold = Threshold<Frequency>;
using CurrentThreshold = Threshold<Current>;

struct ShaftPower {
  static constexpr std::string_view kId = "power";
  static constexpr std::string_view kFormula = "P_r (|T w|/P_rated)^k";
  static constexpr std::string_view kWords = "growing as shaft power^k (torque on the bus)";
  static constexpr double kExponent[3] = {1.0, 0.5, 3.0};
  template <class T, class R>
  static T shape(const EffectInputs<R>& e, const T& k) {
    using std::abs;
    using std::pow;
    if (!e.in.has_torque) return T(0);
    constexpr double kRadPerSPerRpm = 6.283185307179586 / 60.0;
    const R p = abs(e.in.torque_nm * e.in.speed_rpm) * R(kRadPerSPerRpm) / e.motor.rated_power_w;
    return pow(at_least_tiny(p), k);
  }
};

}  // namespace forms

// A form's second parameter: its exponent k, unless the form names another (a threshold).
template <class Form>
constexpr std::string_view second_id() {
  if constexpr (requires { Form::kSecondId; }) return Form::kSecondId; else return "k";
}
template <class Form>
constexpr std::string_view second_description() {
  if constexpr (requires { Form::kSecondDescription; }) return Form::kSecondDescription; else return "the term's exponent k";
}

// A step's form: one with a threshold for its second parameter.
template <class Form>
constexpr bool is_step() {
  return requires { Form::kThresholdWords; };
}

// How a heat term's fitted values read: "... with k = 1.97, 1.19 kW at the rated point", or for a
// step "..., at 72 % of the rated frequency, 719 W above it".
template <class Form>
constexpr std::array<WordPart, 3> heat_words() {
  if constexpr (is_step<Form>())
    return {{{", at ", 1, WordStyle::percent}, {Form::kThresholdWords, 0, WordStyle::watts}, {" above it"}}};
  else
    return {{{" with k = ", 1, WordStyle::fixed2}, {", ", 0, WordStyle::watts}, {" at the rated point"}}};
}

// Extra heat into node `Node`: p[0] W at the rated point (above the threshold, for a step), times
// the form's shape with exponent (or threshold) p[1].
template <int Node, class Form>
struct HeatTerm {
  static constexpr EffectKind kKind = EffectKind::term;
  static constexpr int kNode = Node;
  static constexpr std::string_view kFormula = Form::kFormula;
  static constexpr FixedText kNameText = join({"heat_", kNodeIds[Node], "_", Form::kId});
  static constexpr FixedText kSummaryText = join({"extra heat in the ", kNodeWords[Node], " ", Form::kWords});
  static constexpr FixedText kSizeName = join({kNameText.view(), "_w"});
  static constexpr FixedText kExponentName = join({kNameText.view(), "_", second_id<Form>()});
  // The forms of one node's heat point nearly the same way at their neutral value (a step at its
  // initial threshold too) and share one refit in a diagnosis. Only a step's refit finds where it
  // switches on: it is refit beside its group's where that one is significant (the node needs heat).
  static constexpr FixedText kRefitGroupText = join({"heat_", kNodeIds[Node]});
  static constexpr bool kRefinesGroup = is_step<Form>();
  static constexpr std::string_view kName = kNameText.view();
  static constexpr std::string_view kSummary = kSummaryText.view();
  static constexpr std::string_view kRefitGroup = kRefitGroupText.view();
  static constexpr std::array<WordPart, 3> kWords = heat_words<Form>();
  static constexpr int kExtraStates = 0;
  static constexpr ParamSpec kParams[] = {
      {kSizeName.view(), "W", 500.0, 1.0, 20000.0, 0.0, "the term's heat at the rated point"},
      {kExponentName.view(), "1", Form::kExponent[0], Form::kExponent[1], Form::kExponent[2], Form::kExponent[0],
       second_description<Form>()},
  };

  template <class T, class R>
  static void apply(const EffectInputs<R>& e, const T* p, const StepConductances<T>&, HeatBalance<T>& sys, int) {
    sys.heat(Node, p[0] * Form::template shape<T, R>(e, p[1]));
  }
};

// The conductances to air of one side: the stator's (nodes 1, 2), the rotor's (nodes 3, 4), or
// both sides' (the cooling air itself).
enum class Side { stator, rotor, both };
constexpr int first_node(Side s) { return s == Side::rotor ? kRotorWinding : kStatorWinding; }
constexpr int end_node(Side s) { return s == Side::stator ? kRotorWinding : kNumNodes; }
constexpr std::string_view side_id(Side s) { return s == Side::stator ? "stator" : s == Side::rotor ? "rotor" : "both"; }
constexpr std::string_view side_words(Side s) {
  return s == Side::stator ? "the stator's" : s == Side::rotor ? "the rotor's" : "both sides'";
}
// A term's node: where one side's term acts first; none (-1) for one on both sides.
constexpr int side_node(Side s) { return s == Side::both ? -1 : first_node(s); }

// The side's conductances to air times 1 + a (n/n_b)^k.
template <Side S>
struct SpeedCooling {
  static constexpr EffectKind kKind = EffectKind::term;
  static constexpr int kNode = side_node(S);
  static constexpr std::string_view kFormula = "lambda_air (1 + a (n/n_b)^k)";
  static constexpr FixedText kNameText = join({"cooling_", side_id(S), "_speed"});
  static constexpr FixedText kSummaryText = join({side_words(S), " conductances to air grow with speed^k"});
  static constexpr FixedText kGainName = join({kNameText.view(), "_gain"});
  static constexpr FixedText kExponentName = join({kNameText.view(), "_k"});
  static constexpr std::string_view kName = kNameText.view();
  static constexpr std::string_view kSummary = kSummaryText.view();
  static constexpr WordPart kWords[] = {{" with k = ", 1, WordStyle::fixed2}, {", ", 0, WordStyle::signed_percent},
                                        {" at base speed"}};
  static constexpr int kExtraStates = 0;
  static constexpr ParamSpec kParams[] = {
      {kGainName.view(), "1", 0.3, 0.0, 5.0, 0.0, "relative rise of the conductances to air at base speed"},
      {kExponentName.view(), "1", 1.0, 0.3, 3.0, 1.0, "the rise's exponent k"},
  };

  template <class T, class R>
  static void adjust(const EffectInputs<R>& e, const T* p, StepConductances<T>& g) {
    using std::pow;
    const T factor = T(1) + p[0] * pow(at_least_tiny(e.speed_ratio), p[1]);
    for (int n = first_node(S); n < end_node(S); ++n) g.to_air[n] *= factor;
  }
};

// The side's conductances to air times (V/V_n)^d: eq. 14's exponent changed by d.
template <Side S>
struct AirflowExponent {
  static constexpr EffectKind kKind = EffectKind::term;
  static constexpr int kNode = side_node(S);
  static constexpr std::string_view kFormula = "lambda_air (V/V_n)^(0.8 + d)";
  static constexpr FixedText kNameText = join({"airflow_", side_id(S), "_exponent"});
  static constexpr FixedText kSummaryText =
      join({side_words(S), " conductances to air follow the airflow with another exponent"});
  static constexpr FixedText kChangeName = join({kNameText.view(), "_change"});
  static constexpr std::string_view kName = kNameText.view();
  static constexpr std::string_view kSummary = kSummaryText.view();
  static constexpr WordPart kWords[] = {{": ", 0, WordStyle::plus_0_8}, {" instead of 0.8"}};
  static constexpr int kExtraStates = 0;
  static constexpr ParamSpec kParams[] = {
      {kChangeName.view(), "1", -0.4, -0.7, 0.7, 0.0, "change d of the airflow exponent"},
  };

  template <class T, class R>
  static void adjust(const EffectInputs<R>& e, const T* p, StepConductances<T>& g) {
    using std::pow;
    const T factor = pow(e.effective_airflow_m3s / e.motor.nominal_airflow_m3s, p[0]);
    for (int n = first_node(S); n < end_node(S); ++n) g.to_air[n] *= factor;
  }
};

// A conductance between nodes A and B, which the paper leaves unconnected.
template <int A, int B>
struct Path {
  static constexpr EffectKind kKind = EffectKind::term;
  static constexpr int kNode = A;
  static constexpr std::string_view kFormula = "lambda (T_a - T_b)";
  static constexpr FixedText kNameText = join({"path_", kNodeIds[A], "_", kNodeIds[B]});
  static constexpr FixedText kSummaryText = join({"a heat path between the ", kNodeWords[A], " and the ", kNodeWords[B]});
  static constexpr FixedText kConductanceName = join({kNameText.view(), "_lambda"});
  static constexpr std::string_view kName = kNameText.view();
  static constexpr std::string_view kSummary = kSummaryText.view();
  static constexpr HeatSides kSides = HeatSides::both;  // it links them
  static constexpr WordPart kWords[] = {{" of ", 0, WordStyle::one_decimal}, {" W/K"}};
  static constexpr int kExtraStates = 0;
  static constexpr ParamSpec kParams[] = {
      {kConductanceName.view(), "W/K", 20.0, 0.1, 2000.0, 0.0, "the path's conductance"},
  };

  template <class T, class R>
  static void apply(const EffectInputs<R>&, const T* p, const StepConductances<T>&, HeatBalance<T>& sys, int) {
    sys.path(A, B, p[0]);
  }
};

// A thermal mass behind node `Node`: one extra state T_m with
//     C dT_m/dt = lambda (T_node - T_m) - lambda_air V^0.8 (T_m - T_air)
// and the node losing lambda (T_node - T_m) to it. At lambda = 0 (neutral) it is disconnected. At
// the start of a cycle the mass is soaked through at its node's temperature.
template <int Node>
struct Mass {
  static constexpr EffectKind kKind = EffectKind::term;
  static constexpr int kNode = Node;
  static constexpr std::string_view kFormula = "C dT_m/dt = lambda (T_node - T_m) - lambda_air (V/V_n)^0.8 (T_m - T_air)";
  static constexpr FixedText kNameText = join({"mass_", kNodeIds[Node]});
  static constexpr FixedText kSummaryText = join({"a thermal mass behind the ", kNodeWords[Node]});
  static constexpr FixedText kConductanceName = join({kNameText.view(), "_lambda"});
  static constexpr FixedText kCapacityName = join({kNameText.view(), "_capacity"});
  static constexpr FixedText kAirName = join({kNameText.view(), "_lambda_air"});
  static constexpr std::string_view kName = kNameText.view();
  static constexpr std::string_view kSummary = kSummaryText.view();
  // "... of 581 kJ/K, 288 W/K to it and 135 W/K to the air (time constant 23 min)"
  static constexpr WordPart kWords[] = {{" of ", 1, WordStyle::whole},
                                        {" kJ/K, ", 0, WordStyle::whole},
                                        {" W/K to it and ", 2, WordStyle::whole},
                                        {" W/K to the air (time constant ", -1, WordStyle::whole, true},
                                        {" min)"}};
  // Its time constant in minutes: the capacity over both its conductances.
  static double derived(const double* p) { return p[1] * 1000 / (p[0] + p[2]) / 60; }
  static constexpr int kExtraStates = 1;
  static constexpr ParamSpec kParams[] = {
      {kConductanceName.view(), "W/K", 100.0, 0.1, 5000.0, 0.0, "the mass's conductance to its node"},
      {kCapacityName.view(), "kJ/K", 300.0, 10.0, 50000.0, 300.0, "the mass's heat capacity"},
      {kAirName.view(), "W/K", 50.0, 0.1, 5000.0, 50.0, "the mass's conductance to the cooling air at nominal airflow"},
  };

  template <class T, class R>
  static void apply(const EffectInputs<R>& e, const T* p, const StepConductances<T>&, HeatBalance<T>& sys,
                    int first_state) {
    sys.capacitance[first_state] = p[1] * T(1000);
    sys.path(Node, first_state, p[0]);
    sys.to_fixed(first_state, p[2] * e.airflow_factor, e.in.ambient_c);
  }

  template <class T>
  static void initialize(T* x, int first_state) {
    x[first_state] = x[Node];
  }
};

// Every term, as one entry of the library's list.
using Dictionary = EffectGroup<
    HeatTerm<kStatorWinding, forms::CurrentFrequency>, HeatTerm<kStatorWinding, forms::FluxFrequency>,
    HeatTerm<kStatorWinding, forms::Speed>, HeatTerm<kStatorWinding, forms::ShaftPower>,
    HeatTerm<kStatorCore, forms::CurrentFrequency>, HeatTerm<kStatorCore, forms::FluxFrequency>,
    HeatTerm<kStatorCore, forms::Speed>, HeatTerm<kStatorCore, forms::ShaftPower>,
    HeatTerm<kRotorWinding, forms::CurrentFrequency>, HeatTerm<kRotorWinding, forms::FluxFrequency>,
    HeatTerm<kRotorWinding, forms::Speed>, HeatTerm<kRotorWinding, forms::ShaftPower>,
    HeatTerm<kRotorCore, forms::CurrentFrequency>, HeatTerm<kRotorCore, forms::FluxFrequency>,
    HeatTerm<kRotorCore, forms::Speed>, HeatTerm<kRotorCore, forms::ShaftPower>,
    SpeedCooling<Side::stator>, SpeedCooling<Side::rotor>, AirflowExponent<Side::stator>, AirflowExponent<Side::rotor>,
    Path<kStatorWinding, kRotorWinding>, Path<kStatorWinding, kRotorCore>, Path<kStatorCore, kRotorWinding>,
    Mass<kStatorCore>, Mass<kRotorCore>, Mass<kStatorWinding>,
    // Appended after the first round's terms, so that their parameters keep their indices.
    HeatTerm<kStatorWinding, forms::FrequencyThreshold>, HeatTerm<kStatorWinding, forms::CurrentThreshold>,
    HeatTerm<kStatorCore, forms::FrequencyThreshold>, HeatTerm<kStatorCore, forms::CurrentThreshold>,
    HeatTerm<kRotorWinding, forms::FrequencyThreshold>, HeatTerm<kRotorWinding, forms::CurrentThreshold>,
    HeatTerm<kRotorCore, forms::FrequencyThreshold>, HeatTerm<kRotorCore, forms::CurrentThreshold>,
    SpeedCooling<Side::both>, AirflowExponent<Side::both>>;

}  // namespace lptn::terms
