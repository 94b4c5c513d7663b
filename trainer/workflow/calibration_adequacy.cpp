#include "trainer/workflow/calibration_adequacy.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "hostio/worker_threads.hpp"
#include "trainer/calibrate/calibration_result.hpp"
#include "trainer/calibrate/sensor_noise.hpp"
#include "trainer/diagnose/adequacy.hpp"

namespace lptn::workflow {
namespace {

constexpr data::Channel kSensors[] = {data::Channel::stator_winding_c, data::Channel::rotor_c};
constexpr const char* kSensorNames[] = {"stator", "rotor"};
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// What a warning says after its figures: what to make of them. LM fits the model as closely as the
// data allow, so beyond its noise the model itself falls short; the other methods may only have
// stopped short of that fit (a small budget), which an LM calibration tells.
std::string beyond_and_why(const std::string& method) {
  char within[160];
  std::snprintf(within, sizeof within, " (warned beyond %.1fx): ", kCalibrationAdequateRatio);
  return std::string(within) +
         (method == "lm" ? "it lacks physics this motor has (lptn diagnose finds which), or the training data are too "
                           "short to pin it"
                         : "the method stopped short of the best fit of this model (--method lm finds that one: compare), "
                           "or the model lacks physics this motor has (lptn diagnose finds which)");
}

double worst_rmse(const diagnose::SensorAdequacy& s) {
  return std::isnan(s.test_rmse_k) ? s.train_rmse_k : std::max(s.train_rmse_k, s.test_rmse_k);
}

std::vector<calibrate::CalibrationWarning> inadequate(const std::vector<diagnose::SensorAdequacy>& sensors, const std::string& method) {
  std::vector<calibrate::CalibrationWarning> out;
  for (const diagnose::SensorAdequacy& s : sensors) {
    if (!(worst_rmse(s) > kCalibrationAdequateRatio * s.noise_k)) continue;  // NaN noise: not judged
    out.push_back({"not_adequate",
                   "the model is not adequate on the " + s.sensor + " sensor: " +
                       diagnose::describe(s).substr(s.sensor.size() + 2) + beyond_and_why(method),
                   {}});
  }
  return out;
}

// The sensors' native rates as every process's loader reported them (alone: its own). A cycle that
// balancing moved to another process came without its file's report, and read as sampled every
// step its noise would come out low (interpolation averages it away between readings: 0.26 K for
// 0.40 K on the demo's loop under 2 processes).
data::Dataset reading_rates(calibrate::DatasetRef dataset) {
  nlohmann::json mine = nlohmann::json::array();
  for (const data::CycleReport& c : dataset.data.reports)
    mine.push_back({c.file.string(), c.channels[data::index_of(kSensors[0])].native_rate_hz,
                    c.channels[data::index_of(kSensors[1])].native_rate_hz});
  data::Dataset rates;
  for (const std::string& text : dataset.group().gather(mine.dump()))
    for (const nlohmann::json& c : nlohmann::json::parse(text)) {
      data::CycleReport report;
      report.file = c.at(0).get<std::string>();
      for (int s = 0; s < 2; ++s) report.channels[data::index_of(kSensors[s])].native_rate_hz = c.at(1 + s).get<double>();
      rates.reports.push_back(std::move(report));
    }
  return rates;
}

// Each sensor's noise over `cycles`, each simulated at params_of(cycle) by the process that holds
// it, its sums joined over the processes (the same estimate as adequacy's, summed in another order).
template <class ParamsOf>
std::array<calibrate::NoiseSum, 2> noise_over(const Model<double>& model, const ParamsOf& params_of, calibrate::DatasetRef dataset,
                                   const std::vector<std::size_t>& cycles) {
  const data::Dataset rates = reading_rates(dataset);
  std::vector<std::array<calibrate::NoiseSum, 2>> noise(cycles.size());
  hostio::parallel_for(cycles.size(), hostio::worker_threads(), [&](std::size_t i) {
    if (dataset.remote(cycles[i])) return;
    const data::Cycle& cycle = dataset.cycles[cycles[i]];
    const calibrate::CycleEvaluation e = calibrate::simulate_and_evaluate(model, params_of(cycles[i]), cycle);
    for (int s = 0; s < 2; ++s) {
      if (!cycle.has(kSensors[s])) continue;
      const std::vector<float>& m = s == 0 ? e.simulation.stator_sensor : e.simulation.rotor_sensor;
      std::vector<float> residual(cycle.steps);
      for (std::size_t k = 0; k < cycle.steps; ++k) residual[k] = m[k] - cycle.at(kSensors[s], k);
      noise[i][s] = calibrate::sensor_noise(residual, calibrate::reading_period(rates, cycle, kSensors[s]));
    }
  });
  std::vector<double> sums(4, 0.0);
  for (const auto& cycle : noise)
    for (int s = 0; s < 2; ++s) {
      sums[2 * s] += cycle[s].sum2;
      sums[2 * s + 1] += static_cast<double>(cycle[s].n);
    }
  dataset.group().sum(sums);
  std::array<calibrate::NoiseSum, 2> out;
  for (int s = 0; s < 2; ++s) out[s] = calibrate::NoiseSum{sums[2 * s], static_cast<std::size_t>(sums[2 * s + 1])};
  return out;
}

const ErrorMetrics& side(const calibrate::SplitMetrics& m, int s) { return s == 0 ? m.stator : m.rotor; }

}  // namespace

std::vector<calibrate::CalibrationWarning> score_and_judge_adequacy(calibrate::CalibrationResult& r, const MotorFile& motor,
                                                         calibrate::DatasetRef dataset, const calibrate::Split& split) {
  const Model<double> model = motor.model();
  const ParamVector<double> values = r.values();
  if (!dataset.shared()) {
    // Adequacy's one simulation of every cycle gives evaluate_split's metrics, to the bit.
    diagnose::Adequacy a = diagnose::assess_adequacy(model, values, dataset, split, hostio::worker_threads());
    r.train = std::move(a.train);
    r.test = std::move(a.test);
    return inadequate(a.sensors, r.method);
  }
  calibrate::score_calibration(r, motor, dataset, split);
  std::vector<std::size_t> every = split.train;
  every.insert(every.end(), split.test.begin(), split.test.end());
  const std::array<calibrate::NoiseSum, 2> noise = noise_over(model, [&](std::size_t) { return values; }, dataset, every);
  std::vector<diagnose::SensorAdequacy> sensors;
  for (int s = 0; s < 2; ++s) {
    const ErrorMetrics &train = side(r.train, s), &test = side(r.test, s);
    if (train.samples == 0 && test.samples == 0) continue;  // not measured
    diagnose::SensorAdequacy a;
    a.sensor = kSensorNames[s];
    a.noise_k = noise[s].sigma();
    a.train_rmse_k = train.samples ? train.rmse_k : kNaN;
    a.test_rmse_k = test.samples ? test.rmse_k : kNaN;
    a.adequate = !(worst_rmse(a) > diagnose::kAdequateRatio * a.noise_k);
    sensors.push_back(std::move(a));
  }
  return inadequate(sensors, r.method);
}

std::vector<calibrate::CalibrationWarning> fleet_adequacy(const MotorFile& motor, const fleet::FleetDump& fleet,
                                               const fleet::FleetFit& fit) {
  std::vector<const ParamVector<double>*> params_of(fleet.dataset.data.cycles.size(), nullptr);
  std::vector<std::size_t> every;
  for (std::size_t m = 0; m < fleet.motor_cycles.size() && m < fit.motors.size(); ++m)
    for (std::size_t c : fleet.motor_cycles[m]) {
      params_of[c] = &fit.motors[m].parameters;
      every.push_back(c);
    }
  const std::array<calibrate::NoiseSum, 2> noise =
      noise_over(motor.model(), [&](std::size_t c) { return *params_of[c]; }, fleet.dataset, every);
  // One warning per sensor, naming the motors beyond the ratio, worst first: a fleet of fifty
  // motors that all lack a loss is one finding, not a hundred lines.
  std::vector<calibrate::CalibrationWarning> out;
  for (int s = 0; s < 2; ++s) {
    const double sigma = noise[s].sigma();
    std::size_t measured = 0;
    std::vector<std::pair<double, std::string>> beyond;  // RMSE, motor
    for (const fleet::FleetMotorResult& m : fit.motors) {
      const ErrorMetrics& e = side(m.metrics, s);
      if (e.samples == 0) continue;
      ++measured;
      if (e.rmse_k > kCalibrationAdequateRatio * sigma) beyond.emplace_back(e.rmse_k, m.id);
    }
    if (beyond.empty()) continue;  // NaN noise too: not judged
    std::sort(beyond.begin(), beyond.end(), std::greater<>());
    char figures[240];
    std::snprintf(figures, sizeof figures,
                  "on %zu of %zu motors, each with its own cooling factor: RMSE %.3f..%.3f K over a motor's cycles = "
                  "%.1f..%.1fx the fleet's %s sensor noise of %.3f K (estimated from the readings)",
                  beyond.size(), measured, beyond.back().first, beyond.front().first, beyond.back().first / sigma,
                  beyond.front().first / sigma, kSensorNames[s], sigma);
    std::string worst;
    for (std::size_t i = 0; i < beyond.size() && i < 4; ++i) worst += (i ? ", " : "") + beyond[i].second;
    if (beyond.size() > 4) worst += ", ...";
    out.push_back({"not_adequate",
                   std::string("the model is not adequate on the ") + kSensorNames[s] + " sensor " + figures + " (worst: " +
                       worst + ")" + beyond_and_why("lm"),
                   {}});
  }
  return out;
}

}  // namespace lptn::workflow
