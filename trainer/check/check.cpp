#include "trainer/check/check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>

#include "hostio/bad_input.hpp"
#include "hostio/worker_threads.hpp"
#include "trainer/calibrate/calibration_result.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/fleet/cooling_factor_fit.hpp"

namespace lptn::check {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The figure a calibration claims for a sensor on data it was not fitted on: its test error, or
// its training error where it held no cycle out.
double claimed_error(const calibrate::CalibrationResult& c, int s) {
  const ErrorMetrics& test = s == 0 ? c.test.stator : c.test.rotor;
  const ErrorMetrics& train = s == 0 ? c.train.stator : c.train.rotor;
  if (test.samples > 0) return test.rmse_k;
  if (train.samples > 0) return train.rmse_k;
  return kNaN;
}

const ErrorMetrics& metric(const calibrate::CycleMetrics& m, int s) { return s == 0 ? m.stator : m.rotor; }

std::string percent(double change) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.0f %% %s", std::abs(change) * 100, change < 0 ? "weaker" : "stronger");
  return buf;
}

// "cycle_05 .. cycle_09" style lists: the names, at most four.
std::string names(const std::vector<std::string>& v) {
  std::string out;
  for (std::size_t i = 0; i < v.size() && i < 4; ++i) out += (i ? ", " : "") + v[i];
  if (v.size() > 4) out += ", ... (" + std::to_string(v.size()) + " cycles)";
  return out;
}

// "cooling 28 % weaker than at calibration, from cycle_05": where the changed cycles are the last
// ones of the dump (a filter that clogged), from the first; on every cycle; or the cycles named.
std::string cooling_reason(const Check& c) {
  std::vector<std::size_t> changed;
  for (std::size_t i = 0; i < c.cycles.size(); ++i)
    if (c.cycles[i].cooling_changed) changed.push_back(i);
  if (changed.empty()) return "";
  double sum = 0, weight = 0;
  for (std::size_t i : changed) {
    const double w = 1 / std::max(1e-6, c.cycles[i].cooling_log_std_error * c.cycles[i].cooling_log_std_error);
    sum += w * std::log(c.cycles[i].cooling_factor);
    weight += w;
  }
  const double change = std::exp(sum / weight) - 1;
  std::string out = "cooling " + percent(change) + " than at calibration";
  const bool suffix = changed.back() == c.cycles.size() - 1 && changed.back() - changed.front() + 1 == changed.size();
  if (changed.size() == c.cycles.size()) {
    out += c.cycles.size() == 1 ? " (" + c.cycles.front().name + ")" : " on every cycle";
  } else if (suffix) {
    out += ", from " + c.cycles[changed.front()].name;
  } else {
    std::vector<std::string> n;
    for (std::size_t i : changed) n.push_back(c.cycles[i].name);
    out += " on " + names(n);
  }
  char factor[64];
  std::snprintf(factor, sizeof factor, " (cooling factor %.2f, 1 = as calibrated)", change + 1);
  return out + factor;
}

// "stator error 4.1x its noise on cycle_07, 3.2x the calibration's own test error (3 of 9 cycles
// beyond the bound)": the worst cycle of a sensor beyond its bound.
std::string error_reason(const Check& c, int s) {
  const CycleCheck* worst = nullptr;
  std::size_t beyond = 0;
  for (const CycleCheck& cc : c.cycles) {
    if (!cc.sensors[s].beyond) continue;
    ++beyond;
    if (!worst || cc.sensors[s].rmse_k > worst->sensors[s].rmse_k) worst = &cc;
  }
  if (!worst) return "";
  const SensorCheck& w = worst->sensors[s];
  char line[320];
  std::snprintf(line, sizeof line, "%s error %.2f K on %s: %.1fx its noise of %.2f K", kSensorNames[s], w.rmse_k,
                worst->name.c_str(), w.over_noise, c.noise_k[s]);
  std::string out = line;
  if (std::isfinite(w.over_calibration)) {
    std::snprintf(line, sizeof line, ", %.1fx the calibration's own test error of %.2f K", w.over_calibration,
                  c.calibration_error_k[s]);
    out += line;
  }
  std::snprintf(line, sizeof line, " (%zu of %zu cycles beyond the bound)", beyond, c.cycles.size());
  return out + line;
}

}  // namespace

Check check(const calibrate::CalibrationResult& calibration, const data::Dataset& dataset, const std::optional<MotorFile>& data_motor,
            int threads) {
  if (dataset.cycles.empty()) throw hostio::BadInput("check: the data holds no cycle");
  const MotorFile motor = calibrate::motor_of(calibration);
  const Model<double> model = motor.model();
  const ParamVector<double> params = calibration.values();
  Check c;
  c.provenance = provenance(calibration, dataset, data_motor);
  const std::size_t n = dataset.cycles.size();
  calibrate::Split every;
  every.train.resize(n);
  std::iota(every.train.begin(), every.train.end(), std::size_t{0});
  c.adequacy = diagnose::assess_adequacy(model, params, dataset, every, threads);
  for (const diagnose::SensorAdequacy& a : c.adequacy.sensors) c.noise_k[a.sensor == "rotor"] = a.noise_k;
  for (int s = 0; s < 2; ++s) c.calibration_error_k[s] = claimed_error(calibration, s);

  c.cycles.resize(n);
  hostio::parallel_for(n, threads, [&](std::size_t i) {
    CycleCheck& cc = c.cycles[i];
    const data::Cycle& cycle = dataset.cycles[i];
    cc.name = cycle.name;
    cc.provenance = c.provenance.cycles[i];
    const calibrate::CycleMetrics m = calibrate::evaluate_cycle(model, params, cycle);
    for (int s = 0; s < 2; ++s) {
      SensorCheck& sc = cc.sensors[s];
      if (metric(m, s).samples == 0) continue;
      sc.measured = true;
      sc.rmse_k = metric(m, s).rmse_k;
      sc.over_noise = sc.rmse_k / c.noise_k[s];
      sc.over_calibration = sc.rmse_k / c.calibration_error_k[s];
      // A NaN noise (too few readings) or a sensor the calibration never measured bounds nothing.
      const double by_noise = std::isfinite(c.noise_k[s]) ? diagnose::kAdequateRatio * c.noise_k[s] : 0.0;
      const double by_claim = std::isfinite(c.calibration_error_k[s]) ? kOverCalibrationError * c.calibration_error_k[s] : 0.0;
      const double bound = std::max(by_noise, by_claim);
      sc.beyond = bound > 0 && sc.rmse_k > bound;
    }
    try {
      const fleet::CoolingFactorFit f = fleet::fit_cooling_factor(model, params, dataset, {i}, 1);
      cc.cooling_factor = f.factor;
      cc.cooling_log_std_error = f.log_std_error;
      const double y = std::abs(std::log(f.factor));
      cc.cooling_changed = y >= std::log1p(kMinCoolingChange) && y > kCoolingZ * f.log_std_error;
    } catch (const std::runtime_error&) {  // no sensor on the cycle: nothing to fit
      cc.cooling_factor = kNaN;
      cc.cooling_log_std_error = kNaN;
    }
    cc.holds = !cc.cooling_changed && !cc.sensors[0].beyond && !cc.sensors[1].beyond;
  });

  double sum = 0, weight = 0;
  for (const CycleCheck& cc : c.cycles) {
    if (!std::isfinite(cc.cooling_factor)) continue;
    const double w = 1 / std::max(1e-12, cc.cooling_log_std_error * cc.cooling_log_std_error);
    sum += w * std::log(cc.cooling_factor);
    weight += w;
  }
  if (weight > 0) {
    c.cooling_factor = std::exp(sum / weight);
    c.cooling_log_std_error = std::sqrt(1 / weight);
  }

  if (!c.provenance.constants.empty()) {
    std::string line = "the data's motor.toml has other motor constants than the calibration's: ";
    for (std::size_t i = 0; i < c.provenance.constants.size() && i < 3; ++i)
      line += (i ? ", " : "") + c.provenance.constants[i];
    c.reasons.push_back(line);
  }
  if (std::string r = cooling_reason(c); !r.empty()) c.reasons.push_back(r);
  for (int s = 0; s < 2; ++s)
    if (std::string r = error_reason(c, s); !r.empty()) c.reasons.push_back(r);
  c.holds = c.reasons.empty();
  return c;
}

}  // namespace lptn::check
