// The model: the paper's network plus whichever effects are enabled, and its step.
//
// One Model<R> describes a motor (constants of type R) and a set of effects; its member templates
// take the state and parameters in any scalar T (float, double, ceres::Jet). The parameter vector
// has a fixed layout for every model: the paper's parameters, then each effect's, so a calibration
// result, an exported header and the firmware agree on indices whatever is enabled.
#pragma once

#include <array>
#include <string_view>
#include <type_traits>

#include "lptn/effects/library.hpp"
#include "lptn/heat_balance.hpp"
#include "lptn/integrator.hpp"
#include "lptn/paper_model.hpp"

namespace lptn {

inline constexpr int kNumParams = kNumPaperParams + EffectLibrary::kNumParams;
inline constexpr int kNumEffects = EffectLibrary::kCount;

constexpr const ParamSpec& param_spec(int index) {
  return index < kNumPaperParams ? kPaperParams[index] : EffectLibrary::kParams[index - kNumPaperParams];
}

// Index of a parameter by name, or -1.
constexpr int param_index(std::string_view name) {
  for (int i = 0; i < kNumParams; ++i)
    if (param_spec(i).name == name) return i;
  return -1;
}

// Index of an effect by name, or -1.
constexpr int effect_index(std::string_view name) { return EffectLibrary::index_of(name); }
constexpr EffectSet effect_bit(int effect) { return EffectSet{1} << effect; }

// The effect a parameter belongs to, or -1 for the paper's own parameters.
constexpr int effect_of_param(int index) {
  for (int e = 0; e < kNumEffects; ++e) {
    const int first = kNumPaperParams + EffectLibrary::kParamOffsets[e];
    if (index >= first && index < first + EffectLibrary::kParamCounts[e]) return e;
  }
  return -1;
}

template <class T>
using ParamVector = std::array<T, kNumParams>;

// Every parameter at its spec's initial value.
template <class T>
constexpr ParamVector<T> default_params() {
  ParamVector<T> p{};
  for (int i = 0; i < kNumParams; ++i) p[i] = T(param_spec(i).initial);
  return p;
}

template <class R>
class Model {
 public:
  Model() : Model(MotorConstants<R>{}, 0) {}
  Model(const MotorConstants<R>& motor, EffectSet effects) : motor_(motor), effects_(effects) {
    layout_ = StateLayout{};
    first_state_.fill(-1);
    EffectLibrary::for_each_enabled(effects_, [&](auto index, auto* tag) {
      using E = std::remove_pointer_t<decltype(tag)>;
      first_state_[index] = layout_.n;
      layout_.n += E::kExtraStates;
      if constexpr (requires(StateLayout& s) { E::layout(s, 0); }) E::layout(layout_, first_state_[index]);
    });
  }

  const MotorConstants<R>& motor() const { return motor_; }
  EffectSet effects() const { return effects_; }
  bool has_effect(int effect) const { return (effects_ & effect_bit(effect)) != 0; }
  const StateLayout& layout() const { return layout_; }
  int num_states() const { return layout_.n; }

  // What one step's inputs give before any parameter enters: the losses (eq. 7-13) and eq. 14's
  // airflow factor, three to four pow() calls. A caller that assembles one step with several
  // parameter sets (the observer's sensitivity columns) prepares it once; assemble() from it gives
  // the bits assemble() from the inputs gives.
  struct PreparedInputs {
    Inputs<R> in;
    OperatingLosses<R> losses;
    R speed_ratio;
    R effective_airflow_m3s;
    R airflow_factor;
  };
  PreparedInputs prepare(const Inputs<R>& in) const {
    using std::abs;
    return {in, operating_losses(motor_, in), abs(in.speed_rpm) / motor_.base_speed_rpm(),
            effective_airflow(motor_, in.airflow_m3s), lptn::airflow_factor(motor_, in.airflow_m3s)};
  }

  // The step's linear system dx/dt = A x + c (rate form, ready for the integrator). Returns the
  // step's losses so that callers can report them (and which rotor-loss route was taken).
  template <class T>
  OperatingLosses<R> assemble(const Inputs<R>& in, const T* p, HeatBalance<T>& sys) const {
    const PreparedInputs prepared = prepare(in);
    assemble(prepared, p, sys);
    return prepared.losses;
  }
  template <class T>
  void assemble(const PreparedInputs& step, const T* p, HeatBalance<T>& sys) const {
    assemble_in_power_units(step, p, sys);
    sys.finish();
  }
  // assemble() before its finish(): the network in W/K and W, not yet divided by the capacitances.
  template <class T>
  void assemble_in_power_units(const PreparedInputs& step, const T* p, HeatBalance<T>& sys) const {
    const Inputs<R>& in = step.in;
    const EffectInputs<R> e{motor_, in, step.losses, step.speed_ratio, step.effective_airflow_m3s, step.airflow_factor};

    StepConductances<T> g = paper_conductances(step.airflow_factor, p);
    EffectLibrary::for_each_enabled(effects_, [&](auto index, auto* tag) {
      using E = std::remove_pointer_t<decltype(tag)>;
      const T* ep = p + kNumPaperParams + EffectLibrary::kParamOffsets[index];
      if constexpr (requires { E::adjust(e, ep, g); }) E::adjust(e, ep, g);
    });

    sys.reset(layout_.n);
    assemble_paper_network(motor_, in, step.losses, g, p, sys);
    EffectLibrary::for_each_enabled(effects_, [&](auto index, auto* tag) {
      using E = std::remove_pointer_t<decltype(tag)>;
      const T* ep = p + kNumPaperParams + EffectLibrary::kParamOffsets[index];
      if constexpr (requires { E::apply(e, ep, g, sys, 0); }) E::apply(e, ep, g, sys, first_state_[index]);
    });
  }

  // One fixed step of dt seconds with the inputs held over it. Returns false only if the step's
  // matrix was singular (x is then left as it was).
  template <class T>
  bool step(T* x, const Inputs<R>& in, const T* p, R dt) const {
    StepWorkspace<T> work;
    return step(x, in, p, dt, work);
  }
  // The storage of one step (the network and its factorisation), for a caller that steps many
  // times: with 8-wide Jets, constructing it zeroes some 1,300 doubles, most of a step's own work.
  template <class T>
  struct StepWorkspace {
    HeatBalance<T> sys;
    internal::SmallLu<T> lu;
  };
  template <class T>
  bool step(T* x, const Inputs<R>& in, const T* p, R dt, StepWorkspace<T>& work) const {
    return step(x, prepare(in), p, dt, work);
  }
  template <class T>
  bool step(T* x, const PreparedInputs& in, const T* p, R dt, StepWorkspace<T>& work) const {
    assemble(in, p, work.sys);
    return Sdirk2<T>::step(work.sys, x, dt, work.lu);
  }

  // step() of x and of `count` responses of x to its start (Sdirk2::step_with_responses).
  template <class T>
  bool step_with_responses(T* x, const PreparedInputs& in, const T* p, R dt, StepWorkspace<T>& work,
                           T* const* responses, int count) const {
    assemble(in, p, work.sys);
    return Sdirk2<T>::step_with_responses(work.sys, x, responses, count, dt, work.lu);
  }

  // Start of a cycle: the stator nodes at the stator reading, the rotor nodes at the rotor reading
  // (or, where the rotor is not measured, also the stator reading: a motor that has stood long
  // enough is soaked through), then each effect's extra states.
  template <class T>
  void initial_state(T* x, const T& stator_c, const T& rotor_c) const {
    for (int i = 0; i < kMaxStates; ++i) x[i] = T(0);
    x[kStatorWinding] = stator_c;
    x[kStatorCore] = stator_c;
    x[kRotorWinding] = rotor_c;
    x[kRotorCore] = rotor_c;
    EffectLibrary::for_each_enabled(effects_, [&](auto index, auto* tag) {
      using E = std::remove_pointer_t<decltype(tag)>;
      if constexpr (requires { E::initialize(x, 0); }) E::initialize(x, first_state_[index]);
    });
  }

  // What the temperature sensors read from a state.
  template <class T>
  const T& stator_sensor(const T* x) const { return x[layout_.stator_sensor_state]; }
  template <class T>
  const T& rotor_sensor(const T* x) const { return x[layout_.rotor_sensor_state]; }

 private:
  MotorConstants<R> motor_;
  EffectSet effects_ = 0;
  StateLayout layout_;
  std::array<int, kNumEffects> first_state_{};
};

}  // namespace lptn
