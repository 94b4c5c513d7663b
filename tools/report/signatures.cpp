#include "tools/report/signatures.hpp"

#include <cmath>
#include <functional>

#include "trainer/calibrate/problem.hpp"

namespace lptn::report {
namespace {

using StepValue = std::function<double(const Inputs<double>& in, std::size_t k)>;

std::vector<float> per_step(const data::Cycle& cycle, const StepValue& f) {
  std::vector<float> out(cycle.steps);
  for (std::size_t k = 0; k < cycle.steps; ++k) out[k] = static_cast<float>(f(inputs_at(cycle, k), k));
  return out;
}

double speed_ratio(const Model<double>& model, const Inputs<double>& in) {
  return std::abs(in.speed_rpm) / model.motor().base_speed_rpm();
}

}  // namespace

std::optional<Signature> effect_signature(std::string_view effect, const Model<double>& model,
                                          const ParamVector<double>& params, const data::Cycle& cycle,
                                          const CycleSimulation& sim) {
  const auto& T = sim.nodes;
  const double* p = params.data();
  // airgap.hpp: l_ag (0.25 + 0.75 n/n_base) (T2 - T4); the conductance's own size is what a fit finds.
  if (effect == "airgap")
    return Signature{"(0.25 + 0.75 n/n_base)(T2 - T4), model", "K", per_step(cycle, [&](const Inputs<double>& in, std::size_t k) {
                       return (0.25 + 0.75 * speed_ratio(model, in)) * (T[kStatorCore][k] - T[kRotorCore][k]);
                     })};
  // windage.hpp: P_w ~ (n/n_base)^2 into the rotor core.
  if (effect == "windage")
    return Signature{"(n/n_base)^2", "1", per_step(cycle, [&](const Inputs<double>& in, std::size_t) {
                       const double r = speed_ratio(model, in);
                       return r * r;
                     })};
  // air_heating.hpp: the rotor's air warmed by Q_stator / (rho c_p Vdot), Q_stator through the
  // calibrated stator conductances to air.
  if (effect == "air_heating")
    return Signature{"Q_stator / (rho c_p Vdot), model", "K", per_step(cycle, [&](const Inputs<double>& in, std::size_t k) {
                       const auto g = paper_conductances(model.motor(), in, p);
                       const double q = g.to_air[kStatorWinding] * (T[kStatorWinding][k] - in.ambient_c) +
                                        g.to_air[kStatorCore] * (T[kStatorCore][k] - in.ambient_c);
                       return q / (1206.0 * effective_airflow(model.motor(), in.airflow_m3s));
                     })};
  // rotor_speed_convection.hpp: the rotor's heat to air, scaled by n/n_base.
  if (effect == "rotor_speed_convection")
    return Signature{"n/n_base x rotor heat to air, model", "W", per_step(cycle, [&](const Inputs<double>& in, std::size_t k) {
                       const auto g = paper_conductances(model.motor(), in, p);
                       const double q = g.to_air[kRotorWinding] * (T[kRotorWinding][k] - in.ambient_c) +
                                        g.to_air[kRotorCore] * (T[kRotorCore][k] - in.ambient_c);
                       return speed_ratio(model, in) * q;
                     })};
  // sensor_lag.hpp: a lagging sensor reads T1 - tau dT1/dt.
  if (effect == "sensor_lag")
    return Signature{"dT1/dt, model", "K/s", per_step(cycle, [&](const Inputs<double>&, std::size_t k) {
                       const auto& t1 = T[kStatorWinding];
                       if (k == 0 || k + 1 >= t1.size()) return std::nan("");
                       return (t1[k + 1] - t1[k - 1]) / (2 * cycle.dt_s);
                     })};
  return std::nullopt;
}

std::optional<Signature> refit_signature(std::string_view effect, const std::vector<RefitValue>& values,
                                         const Model<double>& model, const ParamVector<double>& params,
                                         const data::Cycle& cycle, const CycleSimulation& sim) {
  const int e = effect_index(effect);
  if (e < 0) return std::nullopt;
  ParamVector<double> with_params = params;
  for (const RefitValue& v : values)
    if (v.param >= 0 && v.param < kNumParams) with_params[v.param] = v.value;
  const Model<double> with(model.motor(), model.effects() | effect_bit(e));
  const CycleSimulation w = simulate_and_evaluate(with, with_params, cycle).simulation;
  const bool rotor = EffectLibrary::kNodes[static_cast<std::size_t>(e)] >= kRotorWinding;
  const std::vector<float>& a = rotor ? w.rotor_sensor : w.stator_sensor;
  const std::vector<float>& b = rotor ? sim.rotor_sensor : sim.stator_sensor;
  std::vector<float> out(cycle.steps, NAN);
  for (std::size_t k = 0; k < cycle.steps && k < a.size() && k < b.size(); ++k) out[k] = a[k] - b[k];
  return Signature{std::string(rotor ? "rotor" : "stator winding") + " reading, refit with it minus as calibrated", "K",
                   std::move(out)};
}

}  // namespace lptn::report
