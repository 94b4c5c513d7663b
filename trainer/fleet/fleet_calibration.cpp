#include "trainer/fleet/fleet_calibration.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "trainer/calibrate/shared_dataset.hpp"
#include "trainer/model/cooling_factor.hpp"

namespace lptn::fleet {

namespace {
// Each motor's cooling factor against the shared parameters, fitted by the process that holds the
// motor's cycles; on a shared fleet the factors and their errors are then joined over the processes.
void fit_motors(const Model<double>& model, const ParamVector<double>& shared, const FleetDump& fleet, int threads,
                std::vector<FleetMotorResult>& motors) {
  const std::size_t n = motors.size();
  std::vector<double> joined(2 * n, 0.0);
  for (std::size_t m = 0; m < n; ++m) {
    const std::vector<std::size_t>& cycles = fleet.motor_cycles[m];
    if (!cycles.empty() && calibrate::DatasetRef(fleet.dataset).remote(cycles.front())) continue;  // another process's motor
    motors[m].fit = fit_cooling_factor(model, shared, fleet.dataset.data, cycles, threads);
    joined[2 * m] = motors[m].fit.factor;
    joined[2 * m + 1] = motors[m].fit.log_std_error;
  }
  if (!fleet.dataset.shared()) return;
  calibrate::DatasetRef(fleet.dataset).group().sum(joined);
  for (std::size_t m = 0; m < n; ++m) {
    motors[m].fit.factor = joined[2 * m];
    motors[m].fit.log_std_error = joined[2 * m + 1];
  }
}
}  // namespace

FleetFit fit_fleet(const MotorFile& motor, const FleetDump& fleet, const std::vector<std::size_t>& train,
                   const FleetSettings& settings, const std::function<void(const std::string&)>& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto say = [&](const std::string& line) {
    if (progress) progress(line);
  };
  const std::size_t n = fleet.motor_ids.size();
  if (n == 0) throw std::invalid_argument("a fleet without motors");
  std::vector<std::size_t> motor_of(fleet.dataset.data.cycles.size(), 0);
  for (std::size_t m = 0; m < n; ++m)
    for (std::size_t c : fleet.motor_cycles[m]) motor_of[c] = m;
  const Model<double> model = motor.model();

  FleetFit out;
  out.motors.resize(n);
  std::vector<double> log_factor(n, 0.0);
  ParamVector<double> start = motor.initial_values();
  for (int round = 1; round <= settings.max_rounds; ++round) {
    std::vector<double> cooling;
    for (std::size_t c : train) cooling.push_back(std::exp(log_factor[motor_of[c]]));
    char line[200];
    std::snprintf(line, sizeof line, "round %d: the motor type's parameters (LM) on %zu cycles of %zu motors", round,
                  train.size(), n);
    say(line);
    out.shared = lm::fit_lm(motor, start, fleet.dataset, train, settings.lm, {}, cooling);
    std::vector<double> next(n);
    fit_motors(model, out.shared.values, fleet, settings.lm.threads, out.motors);
    for (std::size_t m = 0; m < n; ++m) next[m] = std::log(out.motors[m].fit.factor);
    // The fleet's median motor cools as the shared parameters say.
    const double mid = median(next);
    for (double& x : next) x -= mid;
    for (int i : kConductancesToAir) {
      out.shared.values[i] *= std::exp(mid);
      out.shared.std_error[i] *= std::exp(mid);
    }
    double moved = 0;
    for (std::size_t m = 0; m < n; ++m) moved = std::max(moved, std::abs(next[m] - log_factor[m]));
    log_factor = next;
    start = out.shared.values;
    out.rounds = round;
    std::snprintf(line, sizeof line, "round %d: shared fit rmse %.3f K; motors' cooling factors moved by up to %.2g",
                  round, out.shared.rmse_k, moved);
    say(line);
    if (moved < settings.round_tolerance) break;
  }

  std::vector<MotorFactor> factors(n);
  for (std::size_t m = 0; m < n; ++m) factors[m] = {log_factor[m], out.motors[m].fit.log_std_error};
  const std::vector<OutlierVerdict> verdicts = fleet_outliers(factors, settings.family_alpha);
  double mean = 0;
  for (double x : log_factor) mean += x / static_cast<double>(n);
  double ss = 0;
  for (double x : log_factor) ss += (x - mean) * (x - mean);
  out.log_factor_spread = n > 1 ? std::sqrt(ss / static_cast<double>(n - 1)) : 0.0;
  for (std::size_t m = 0; m < n; ++m) {
    FleetMotorResult& r = out.motors[m];
    r.id = fleet.motor_ids[m];
    r.cooling_factor = std::exp(log_factor[m]);
    r.cooling_factor_std = r.cooling_factor * r.fit.log_std_error;
    r.fit.factor = r.cooling_factor;  // as normalized
    r.parameters = with_cooling_factor(out.shared.values, r.cooling_factor);
    r.metrics = calibrate::evaluate_split(model, r.parameters, fleet.dataset, fleet.motor_cycles[m], settings.lm.threads);
    r.verdict = verdicts[m];
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace lptn::fleet
