// The model run over a fleet-dump cycle: the one loop that simulation, comparison and the
// calibrators share (templated so that calibrators can run it with Jets).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

#include "lptn/lanes.hpp"
#include "lptn/model.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn::model {

// The model's inputs at grid step k. Torque and voltage count as on the bus where they have a
// value; the model falls back to the nameplate route for the steps where they do not.
inline Inputs<double> inputs_at(const data::Cycle& cycle, std::size_t k) {
  using data::Channel;
  Inputs<double> in;
  in.speed_rpm = cycle.at(Channel::speed_rpm, k);
  in.current_a = cycle.at(Channel::current_a, k);
  in.frequency_hz = cycle.at(Channel::frequency_hz, k);
  in.airflow_m3s = cycle.at(Channel::airflow_m3s, k);
  in.ambient_c = cycle.at(Channel::ambient_c, k);
  const float torque = cycle.at(Channel::torque_nm, k);
  const float voltage = cycle.at(Channel::voltage_v, k);
  in.has_torque = !std::isnan(torque);
  in.has_voltage = !std::isnan(voltage);
  in.torque_nm = in.has_torque ? torque : 0.0;
  in.voltage_v = in.has_voltage ? voltage : 0.0;
  return in;
}

// A cycle's inputs as the model prepares them at every grid step (Model::prepare: the losses and
// the airflow factor, which no parameter changes), for a caller that simulates one cycle with many
// parameter sets (TD3's and the search methods' scorer): their pow() calls were a fifth of such a
// simulation. 152 bytes a step: 4 MB for 7 h on the 1 s grid.
using PreparedCycle = std::vector<Model<double>::PreparedInputs>;
inline PreparedCycle prepare_cycle(const Model<double>& model, const data::Cycle& cycle) {
  PreparedCycle out;
  out.reserve(cycle.steps);
  for (std::size_t k = 0; k < cycle.steps; ++k) out.push_back(model.prepare(inputs_at(cycle, k)));
  return out;
}

// The first valid value of a channel (NaN if there is none).
inline double first_valid(const data::Cycle& cycle, data::Channel channel) {
  for (std::size_t k = 0; k < cycle.steps; ++k) {
    const float v = cycle.at(channel, k);
    if (!std::isnan(v)) return v;
  }
  return std::nan("");
}

// The nodes no sensor sees start at the rule's value plus these offsets (K). Calibration
// estimates them per cycle (initial_offsets.hpp beside this file); zero means the
// rule alone.
template <class T>
struct InitialOffsets {
  T stator_core = T(0);
  T rotor_core = T(0);
};

// Initial temperatures (docs/model.md "The model"): each measured node starts at its sensor's first
// reading. The nodes no sensor sees start where a motor that has stood would be, soaked through:
// the stator core at the stator winding's reading, the rotor core at the rotor reading (where the
// rotor is not measured, both rotor nodes at the stator's), plus the cycle's offsets.
template <class T>
void initial_state_for(const Model<double>& model, const data::Cycle& cycle, T* x,
                       const InitialOffsets<T>& offsets = {}) {
  const double stator = first_valid(cycle, data::Channel::stator_winding_c);
  const double rotor = first_valid(cycle, data::Channel::rotor_c);
  model.initial_state(x, T(stator), T(std::isnan(rotor) ? stator : rotor));
  x[kStatorCore] = x[kStatorCore] + offsets.stator_core;
  x[kRotorCore] = x[kRotorCore] + offsets.rotor_core;
  if (std::isnan(rotor)) x[kRotorWinding] = x[kRotorWinding] + offsets.rotor_core;
}

// Runs the model over the whole cycle (or its first `max_steps` grid steps); on_step(k, x) sees
// the state after step k's inputs were applied for one step, i.e. the estimate for grid time
// t0 + (k + 1) dt. Grid step 0 is the initial state itself and is passed as on_step(-1, x) first.
// `prepared`, where given, is prepare_cycle()'s for this model and cycle: the same steps, without
// computing the losses again.
template <class T, class OnStep>
void run_cycle(const Model<double>& model, const T* params, const data::Cycle& cycle, OnStep&& on_step,
               const InitialOffsets<T>& offsets = {}, std::size_t max_steps = SIZE_MAX,
               const PreparedCycle* prepared = nullptr) {
  T x[kMaxStates];
  initial_state_for(model, cycle, x, offsets);
  on_step(std::ptrdiff_t{-1}, static_cast<const T*>(x));
  const std::size_t steps = std::min(cycle.steps, max_steps);
  typename Model<double>::template StepWorkspace<T> work;
  for (std::size_t k = 0; k + 1 < steps; ++k) {
    if (prepared)
      model.step(x, (*prepared)[k], params, cycle.dt_s, work);
    else
      model.step(x, inputs_at(cycle, k), params, cycle.dt_s, work);
    on_step(static_cast<std::ptrdiff_t>(k), static_cast<const T*>(x));
  }
}

// One step of L parameter sets at once (lanes.hpp), x and `count` responses of x to its start
// beside it (Model::step_with_responses), each lane with the bits a double's step gives params[l]
// (p: the same sets packed). A step whose lanes would pivot differently, or whose matrix is
// singular in a lane, is taken lane by lane as doubles.
template <int L>
struct LaneStepper {
  const Model<double>& model;
  const ParamVector<double>* params;  // L sets
  Lanes<L> p[kNumParams];
  typename Model<double>::template StepWorkspace<Lanes<L>> work;
  typename Model<double>::template StepWorkspace<double> apart;

  LaneStepper(const Model<double>& m, const ParamVector<double>* sets) : model(m), params(sets) {
    for (int l = 0; l < L; ++l)
      for (int i = 0; i < kNumParams; ++i) p[i].set_lane(l, params[l][i]);
  }
  void step(Lanes<L>* x, const Model<double>::PreparedInputs& in, double dt, Lanes<L>* const* responses = nullptr,
            int count = 0) {
    if (model.step_with_responses(x, in, p, dt, work, responses, count)) return;
    for (int l = 0; l < L; ++l) {
      double xl[kMaxStates], rl[kMaxStates][kMaxStates];
      double* rp[kMaxStates];
      for (int i = 0; i < kMaxStates; ++i) xl[i] = x[i].lane(l);
      for (int r = 0; r < count; ++r) {
        rp[r] = rl[r];
        for (int i = 0; i < kMaxStates; ++i) rl[r][i] = responses[r][i].lane(l);
      }
      model.step_with_responses(xl, in, params[l].data(), dt, apart, rp, count);
      for (int i = 0; i < kMaxStates; ++i) x[i].set_lane(l, xl[i]);
      for (int r = 0; r < count; ++r)
        for (int i = 0; i < kMaxStates; ++i) responses[r][i].set_lane(l, rl[r][i]);
    }
  }
};

// LaneStepper's interface for one set of doubles (SetStepper<1>), for code written once for both.
struct DoubleStepper {
  const Model<double>& model;
  const ParamVector<double>* params;  // one set
  Model<double>::StepWorkspace<double> work;

  DoubleStepper(const Model<double>& m, const ParamVector<double>* set) : model(m), params(set) {}
  void step(double* x, const Model<double>::PreparedInputs& in, double dt, double* const* responses = nullptr,
            int count = 0) {
    model.step_with_responses(x, in, params->data(), dt, work, responses, count);
  }
};
template <int L>
using SetStepper = std::conditional_t<L == 1, DoubleStepper, LaneStepper<L>>;

// run_cycle() for L parameter sets at once: on_step(k, x) sees the L states packed, lane l the
// state run_cycle() gives params[l] and offsets[l], to the bit. For a caller that scores many sets
// on one cycle (the set scorer).
template <int L, class OnStep>
void run_cycle_lanes(const Model<double>& model, const ParamVector<double>* params, const data::Cycle& cycle,
                     OnStep&& on_step, const InitialOffsets<double>* offsets, const PreparedCycle* prepared = nullptr) {
  using T = Lanes<L>;
  InitialOffsets<T> lane_offsets;
  for (int l = 0; l < L; ++l) {
    lane_offsets.stator_core.set_lane(l, offsets[l].stator_core);
    lane_offsets.rotor_core.set_lane(l, offsets[l].rotor_core);
  }
  T x[kMaxStates];
  initial_state_for(model, cycle, x, lane_offsets);
  on_step(std::ptrdiff_t{-1}, static_cast<const T*>(x));
  LaneStepper<L> stepper(model, params);
  Model<double>::PreparedInputs computed{};
  for (std::size_t k = 0; k + 1 < cycle.steps; ++k) {
    stepper.step(x, prepared ? (*prepared)[k] : (computed = model.prepare(inputs_at(cycle, k))), cycle.dt_s);
    on_step(static_cast<std::ptrdiff_t>(k), static_cast<const T*>(x));
  }
}

// A cycle's simulated temperatures on the grid.
struct CycleSimulation {
  std::string name;
  std::vector<float> nodes[kNumNodes];
  std::vector<float> stator_sensor;  // what the stator sensor would read (differs from node 1 with sensor_lag)
  std::vector<float> rotor_sensor;
};

// `prepared`, where given, is prepare_cycle()'s for this model and cycle (run_cycle).
CycleSimulation simulate_cycle(const Model<double>& model, const ParamVector<double>& params, const data::Cycle& cycle,
                               const InitialOffsets<double>& offsets = {}, const PreparedCycle* prepared = nullptr);

// Model-minus-measurement statistics over the steps where the measurement exists.
struct ErrorMetrics {
  double rmse_k = 0;
  double mean_abs_k = 0;
  double max_abs_k = 0;
  double bias_k = 0;  // mean of model - measured
  std::size_t samples = 0;
};

// The statistics accumulated one step at a time: compare() over a stored simulation, or a caller
// that needs the metrics alone and compares as it runs (evaluate_cycle: the same sums in the same
// order, so the same bits, without storing every node of every step).
class ErrorSum {
 public:
  // One step: the model's value (as a simulation stores it, in float) against the reading (NaN: none).
  void add(float model, float measured) {
    if (std::isnan(measured)) return;
    const double e = static_cast<double>(model) - measured;
    sum_ += e;
    sum_sq_ += e * e;
    sum_abs_ += std::abs(e);
    max_abs_ = std::max(max_abs_, std::abs(e));
    ++samples_;
  }
  ErrorMetrics metrics() const;

 private:
  double sum_ = 0, sum_sq_ = 0, sum_abs_ = 0, max_abs_ = 0;
  std::size_t samples_ = 0;
};

ErrorMetrics compare(const std::vector<float>& model, const data::Cycle& cycle, data::Channel measured);
// Pools several cycles' metrics into one (weighted by samples).
ErrorMetrics pool(const std::vector<ErrorMetrics>& parts);

}  // namespace lptn::model
