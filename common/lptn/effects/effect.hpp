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
};

// Where each state lives; fixed once the set of effects is chosen.
struct StateLayout {
  int n = kNumNodes;
  int stator_sensor_state = kStatorWinding;  // the state the stator winding sensor reads
  int rotor_sensor_state = kRotorWinding;    // the state a rotor telemetry sensor reads
};

}  // namespace lptn
