// What an effect is: one small struct of model code beyond the paper, switched on by name.
//
// An effect is a struct with
//   static constexpr std::string_view kName;      // its name in motor files and on the command line
//   static constexpr std::string_view kSummary;   // one line for --help and reports
//   static constexpr int kExtraStates;            // states it adds after the four nodes (0 for most)
//   static constexpr ParamSpec kParams[];         // its parameters, with units, bounds and `neutral`,
//                                                 // the value at which it does nothing
// and any of these hooks (a missing hook is simply not called):
//   template <class T, class R>
//   static void adjust(const EffectInputs<R>&, const T* p, StepConductances<T>& g);
//       change the paper's conductances before the network is assembled (e.g. scale with speed);
//   template <class T, class R>
//   static void apply(const EffectInputs<R>&, const T* p, const StepConductances<T>& g,
//                     HeatBalance<T>& sys, int first_state);
//       add heat paths, losses or couplings to the assembled network;
//   static void layout(StateLayout& s, int first_state);
//       claim its extra states (and e.g. redirect which state a sensor reads);
//   template <class T> static void initialize(T* x, int first_state);
//       set its extra states at the start of a cycle, once the nodes are set.
// A dictionary term (effects/dictionary.hpp) also declares
//   static constexpr EffectKind kKind = EffectKind::term;
//   static constexpr int kNode;                  // the node it acts on (the first, for a path)
//   static constexpr std::string_view kFormula;  // its form, e.g. "P (I/I_r)^2 (f/f_r)^k"
// An effect without kKind is a library effect: physics with a name and a reference.
// What a diagnosis needs to know of an effect lives with it too (each optional, with the default
// in brackets; trainer/diagnose reads them, nothing else does):
//   static constexpr std::string_view kNeeds;    // the data that tell it apart from what the model
//                                                // has ["data in which its inputs vary independently
//                                                // of load and airflow"]
//   static constexpr HeatSides kSides;           // the sides its heat flows through [a term's node's
//                                                // side; both for a library effect]
//   static constexpr double kScoreAt;            // where the score test evaluates its first
//                                                // parameter [its neutral value]
//   static constexpr std::string_view kRefitGroup;  // terms of one group share one refit [its name]
//   static constexpr bool kRefinesGroup;         // refit only where its group's refit is
//                                                // significant, beside it [false]
//   static constexpr WordPart kWords[];          // how its fitted values read [its summary, then
//                                                // each parameter with its unit]
//   static double derived(const double* p);      // a value its words show beside its parameters
// and, for a library effect, what lptn report plots the residual against (its "signature": what
// it would add, per step, up to its size):
//   static constexpr std::string_view kSignatureLabel, kSignatureUnit;
//   template <class R> static R signature(const SignatureInputs<R>&);
// `p` points at the effect's own parameters, in the order of kParams. Registering an effect is one
// line in effects/library.hpp. Effects must keep the model linear in the state (the integrator's
// premise) and, like all of common/, allocate nothing and throw nothing.
#pragma once

#include <string_view>

#include "lptn/heat_balance.hpp"
#include "lptn/inputs.hpp"
#include "lptn/motor_constants.hpp"
#include "lptn/paper_model.hpp"
#include "lptn/params.hpp"

namespace lptn {

// Library effects are named physics with a reference; dictionary terms are generic forms diagnose
// tries when no library effect explains the data (PySINDy's dictionary of candidate terms).
enum class EffectKind { library, term };

// What every effect may read about the present step (all of type R: inputs and constants).
template <class R>
struct EffectInputs {
  const MotorConstants<R>& motor;
  const Inputs<R>& in;
  const OperatingLosses<R>& losses;
  R speed_ratio;          // |n| / base speed
  R effective_airflow_m3s;  // the airflow with the natural-convection floor of eq. 14 applied
  R airflow_factor;       // eq. 14's factor on the conductances to the air at this airflow
};

// The sides of the network an effect's heat flows through (bits): the paper leaves stator and
// rotor unconnected, so a parameter on one side cannot stand in for an effect on the other.
enum class HeatSides : unsigned { stator = 1, rotor = 2, both = 3 };

// One piece of an effect's words: text, then (param >= 0) parameter `param` of the effect, or
// (derived) the effect's derived value, printed as `style` says.
enum class WordStyle {
  none,      // the text alone
  fixed2,    // 1.97
  watts,     // 719 W, 1.19 kW
  percent,   // a share as 72 %
  signed_percent,  // a relative change as +30 %
  whole,     // 581
  one_decimal,  // 20.3
  plus_0_8,  // an exponent change d as the exponent 0.8 + d
};
struct WordPart {
  std::string_view text;
  int param = -1;
  WordStyle style = WordStyle::none;
  bool derived = false;
};

// What an effect's signature may read at one step of a simulated cycle.
template <class R>
struct SignatureInputs {
  const MotorConstants<R>& motor;
  const Inputs<R>& in;
  const R* params;         // the whole parameter vector (the paper's conductances among them)
  const R* nodes;          // the four nodes' temperatures
  R winding_rate_k_per_s;  // dT1/dt (NaN at a cycle's ends)
  R speed_ratio() const {
    using std::abs;
    return abs(in.speed_rpm) / motor.base_speed_rpm();
  }
};

// Where each state lives; fixed once the set of effects is chosen.
struct StateLayout {
  int n = kNumNodes;
  int stator_sensor_state = kStatorWinding;  // the state the stator winding sensor reads
  int rotor_sensor_state = kRotorWinding;    // the state a rotor telemetry sensor reads
};

}  // namespace lptn
