#include "trainer/model/simulate.hpp"

#include <algorithm>

namespace lptn::model {
namespace {

// The statistics from running sums over `samples` residuals.
ErrorMetrics finish(double sum, double sum_sq, double sum_abs, double max_abs, std::size_t samples) {
  ErrorMetrics m;
  m.max_abs_k = max_abs;
  m.samples = samples;
  if (samples > 0) {
    const double n = static_cast<double>(samples);
    m.rmse_k = std::sqrt(sum_sq / n);
    m.mean_abs_k = sum_abs / n;
    m.bias_k = sum / n;
  }
  return m;
}

}  // namespace

CycleSimulation simulate_cycle(const Model<double>& model, const ParamVector<double>& params, const data::Cycle& cycle,
                               const InitialOffsets<double>& offsets, const PreparedCycle* prepared) {
  CycleSimulation out;
  out.name = cycle.name;
  for (auto& v : out.nodes) v.reserve(cycle.steps);
  out.stator_sensor.reserve(cycle.steps);
  out.rotor_sensor.reserve(cycle.steps);
  run_cycle(model, params.data(), cycle, [&](std::ptrdiff_t, const double* x) {
    for (int i = 0; i < kNumNodes; ++i) out.nodes[i].push_back(static_cast<float>(x[i]));
    out.stator_sensor.push_back(static_cast<float>(model.stator_sensor(x)));
    out.rotor_sensor.push_back(static_cast<float>(model.rotor_sensor(x)));
  }, offsets, SIZE_MAX, prepared);
  return out;
}

ErrorMetrics ErrorSum::metrics() const { return finish(sum_, sum_sq_, sum_abs_, max_abs_, samples_); }

ErrorMetrics compare(const std::vector<float>& model, const data::Cycle& cycle, data::Channel measured) {
  ErrorSum errors;
  const std::size_t n = std::min(model.size(), cycle.steps);
  for (std::size_t k = 0; k < n; ++k) errors.add(model[k], cycle.at(measured, k));
  return errors.metrics();
}

ErrorMetrics pool(const std::vector<ErrorMetrics>& parts) {
  double sum = 0, sum_sq = 0, sum_abs = 0, max_abs = 0;
  std::size_t samples = 0;
  for (const ErrorMetrics& p : parts) {
    const double n = static_cast<double>(p.samples);
    sum += p.bias_k * n;
    sum_sq += p.rmse_k * p.rmse_k * n;
    sum_abs += p.mean_abs_k * n;
    max_abs = std::max(max_abs, p.max_abs_k);
    samples += p.samples;
  }
  return finish(sum, sum_sq, sum_abs, max_abs, samples);
}

}  // namespace lptn::model
