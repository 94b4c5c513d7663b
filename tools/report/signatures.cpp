#include "tools/report/signatures.hpp"

#include <cmath>
#include <functional>
#include <type_traits>

#include "trainer/calibrate/problem.hpp"

namespace lptn::report {
namespace {

using StepValue = std::function<double(const Inputs<double>& in, std::size_t k)>;

std::vector<float> per_step(const data::Cycle& cycle, const StepValue& f) {
  std::vector<float> out(cycle.steps);
  for (std::size_t k = 0; k < cycle.steps; ++k) out[k] = static_cast<float>(f(inputs_at(cycle, k), k));
  return out;
}

}  // namespace

std::optional<Signature> effect_signature(std::string_view effect, const Model<double>& model,
                                          const ParamVector<double>& params, const data::Cycle& cycle,
                                          const CycleSimulation& sim) {
  const int e = effect_index(effect);
  if (e < 0) return std::nullopt;
  std::optional<Signature> out;
  // The effect's own signature (its kSignatureLabel and signature(), common/lptn/effects/).
  EffectLibrary::for_each_enabled(effect_bit(e), [&](auto, auto* type) {
    using E = std::remove_pointer_t<decltype(type)>;
    if constexpr (requires { E::kSignatureLabel; }) {
      const auto& T = sim.nodes;
      out = Signature{std::string(E::kSignatureLabel), std::string(E::kSignatureUnit),
                      per_step(cycle, [&](const Inputs<double>& in, std::size_t k) {
                        const double nodes[kNumNodes] = {T[kStatorWinding][k], T[kStatorCore][k], T[kRotorWinding][k],
                                                         T[kRotorCore][k]};
                        const auto& t1 = T[kStatorWinding];
                        const double rate = k == 0 || k + 1 >= t1.size() ? std::nan("")
                                                                          : (t1[k + 1] - t1[k - 1]) / (2 * cycle.dt_s);
                        return E::signature(SignatureInputs<double>{model.motor(), in, params.data(), nodes, rate});
                      })};
    }
  });
  return out;
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
  const CycleSimulation w = calibrate::simulate_and_evaluate(with, with_params, cycle).simulation;
  const bool rotor = EffectLibrary::kNodes[static_cast<std::size_t>(e)] >= kRotorWinding;
  const std::vector<float>& a = rotor ? w.rotor_sensor : w.stator_sensor;
  const std::vector<float>& b = rotor ? sim.rotor_sensor : sim.stator_sensor;
  std::vector<float> out(cycle.steps, NAN);
  for (std::size_t k = 0; k < cycle.steps && k < a.size() && k < b.size(); ++k) out[k] = a[k] - b[k];
  return Signature{std::string(rotor ? "rotor" : "stator winding") + " reading, refit with it minus as calibrated", "K",
                   std::move(out)};
}

}  // namespace lptn::report
