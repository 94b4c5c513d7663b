#include "tools/report/report.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <iterator>
#include <optional>
#include <utility>

#include "hostio/utc_stamp.hpp"
#include "hostio/worker_threads.hpp"
#include "lptn/model.hpp"
#include "tools/report/fleet_section.hpp"
#include "trainer/data/data_map.hpp"
#include "tools/report/signatures.hpp"
#include "tools/report/stats.hpp"
#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/calibrate/calibration_outcome.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/calibrate/sensor_noise.hpp"
#include "trainer/check/check.hpp"
#include "trainer/check/sensor_corrections.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/diagnose/diagnose.hpp"
#include "trainer/diagnose/diagnosis_file.hpp"
#include "trainer/model/motor_file.hpp"
#include "trainer/model/simulate.hpp"

namespace lptn::report {
namespace {

using data::Channel;
using nlohmann::json;

// Chart points per cycle: about two per pixel of a wide screen, so a nine-cycle, 11-hour dump
// stays a few MB; zooming in shows each bucket's min and max, so no spike is lost.
constexpr std::size_t kMaxChartPoints = 3000;
// Statistics run on 1 s means: the sensors report at 1 Hz, so 10 Hz residuals are interpolations
// whose neighbours are correlated by construction.
constexpr double kStatStepS = 1.0;
constexpr std::size_t kMaxLagS = 1200;          // correlations out to 20 minutes (thermal time constants)
constexpr std::size_t kWindowS = 300;           // worst windows: 5 minutes,
constexpr std::size_t kWindowStrideS = 30;      // tried every 30 s,
constexpr std::size_t kWorstWindows = 10;       // the ten worst
constexpr std::size_t kLeadingCandidates = 3;   // diagnose candidates with an evidence plot
constexpr std::size_t kSignatureBins = 20;

// One cycle with the calibrated model run over it.
struct CycleRun {
  const data::Cycle* cycle = nullptr;
  // "train" or "test" where the calibration was fitted or tested on this very file (name and hash),
  // "unseen" where it never saw it (a cycle of the same name in another file included), else "".
  std::string role;
  CycleSimulation sim;
  calibrate::CycleMetrics metrics;
  std::vector<float> stator_residual, rotor_residual;  // model - measured, per grid step
  // Grid steps between a sensor's own readings (the loader interpolates between them).
  std::size_t stator_period = 1, rotor_period = 1;
};

// The sensors a residual exists for. Every view of "where it fails" is made for each of them: the
// paper's model can fit the stator winding to its noise while the rotor is 8 K off (a missing
// windage), and a report of the stator alone would show nothing.
struct SensorDef {
  const char* key;    // the page's name for it
  const char* label;  // for people
  Channel measured;
  std::vector<float> CycleRun::*residual;
  std::size_t CycleRun::*period;
};
constexpr SensorDef kSensors[] = {
    {"stator", "stator winding", Channel::stator_winding_c, &CycleRun::stator_residual, &CycleRun::stator_period},
    {"rotor", "rotor", Channel::rotor_c, &CycleRun::rotor_residual, &CycleRun::rotor_period}};

// The model a calibration describes: its motor text, effects and parameter values.
struct CalibratedModel {
  Model<double> model;
  ParamVector<double> params;
};

double rounded(double v, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::round(v * scale) / scale;
}

// NaN becomes null (a gap for dygraphs); fixed decimals keep the page small.
json numbers(const std::vector<double>& v, int decimals) {
  json a = json::array();
  for (double d : v) a.push_back(std::isfinite(d) ? json(rounded(d, decimals)) : json(nullptr));
  return a;
}

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json metrics_json(const ErrorMetrics& m) {
  return {{"rmse_k", m.rmse_k}, {"mean_abs_k", m.mean_abs_k}, {"max_abs_k", m.max_abs_k},
          {"bias_k", m.bias_k}, {"samples", m.samples}};
}

std::vector<std::string> effect_names(EffectSet effects) {
  std::vector<std::string> names;
  for (int i = 0; i < EffectLibrary::kCount; ++i) {
    if (effects & effect_bit(i)) names.emplace_back(EffectLibrary::kNames[static_cast<std::size_t>(i)]);
  }
  return names;
}

CalibratedModel calibrated_model(const calibrate::CalibrationResult& cal) {
  return {Model<double>(cal.motor.constants, cal.effects), cal.values()};
}

// Never by name alone: a drive of another motor, or of the same motor a month later, may carry the
// calibration's cycle names.
std::string role_of(const check::CycleProvenance& p) { return p.seen ? p.role : "unseen"; }

std::vector<float> residual(const std::vector<float>& model, const data::Cycle& cycle, Channel measured) {
  std::vector<float> r(cycle.steps);
  for (std::size_t k = 0; k < cycle.steps; ++k) r[k] = model[k] - cycle.at(measured, k);
  return r;
}

// As calibrate evaluates a cycle for its metrics (simulate_and_evaluate), with the residuals kept.
CycleRun run_cycle_model(const CalibratedModel& cm, const data::Cycle& cycle, const std::string& role) {
  CycleRun run;
  run.cycle = &cycle;
  run.role = role;
  calibrate::CycleEvaluation e = calibrate::simulate_and_evaluate(cm.model, cm.params, cycle);
  run.sim = std::move(e.simulation);
  run.metrics = std::move(e.metrics);
  run.stator_residual = residual(run.sim.stator_sensor, cycle, Channel::stator_winding_c);
  run.rotor_residual = residual(run.sim.rotor_sensor, cycle, Channel::rotor_c);
  return run;
}

std::size_t steps_per_stat(const data::Cycle& cycle) {
  return std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(kStatStepS / cycle.dt_s)));
}

// A whole channel, or all-NaN where the file has no such column.
std::vector<float> channel(const data::Cycle& cycle, Channel c) {
  const auto& v = cycle.samples[data::index_of(c)];
  return v.empty() ? std::vector<float>(cycle.steps, std::nanf("")) : v;
}

// --- Compare ------------------------------------------------------------------------------------

json envelope_json(const std::vector<float>& v, std::size_t bucket, int decimals) {
  const Envelope e = envelope(v, bucket);
  return {{"lo", numbers(e.lo, decimals)}, {"mean", numbers(e.mean, decimals)}, {"hi", numbers(e.hi, decimals)}};
}

json compare_cycle(const CycleRun& run) {
  const data::Cycle& c = *run.cycle;
  const std::size_t bucket = std::max<std::size_t>(steps_per_stat(c), (c.steps + kMaxChartPoints - 1) / kMaxChartPoints);
  std::vector<double> t;
  for (std::size_t k = 0; k < c.steps; k += bucket) t.push_back(c.time_s(k));
  json series = {
      {"stator_measured", envelope_json(channel(c, Channel::stator_winding_c), bucket, 2)},
      {"stator_model", envelope_json(run.sim.stator_sensor, bucket, 2)},
      {"stator_residual", envelope_json(run.stator_residual, bucket, 3)},
      {"speed", envelope_json(channel(c, Channel::speed_rpm), bucket, 0)},
      {"torque", envelope_json(channel(c, Channel::torque_nm), bucket, 0)},
      {"airflow", envelope_json(channel(c, Channel::airflow_m3s), bucket, 3)},
      {"ambient", envelope_json(channel(c, Channel::ambient_c), bucket, 2)},
  };
  const bool rotor = run.metrics.rotor.samples > 0;
  if (rotor) {
    series["rotor_measured"] = envelope_json(channel(c, Channel::rotor_c), bucket, 2);
    series["rotor_model"] = envelope_json(run.sim.rotor_sensor, bucket, 2);
    series["rotor_residual"] = envelope_json(run.rotor_residual, bucket, 3);
  }
  json metrics = {{"stator", metrics_json(run.metrics.stator)}};
  if (rotor) metrics["rotor"] = metrics_json(run.metrics.rotor);
  return {{"name", c.name}, {"role", run.role}, {"bucket_s", static_cast<double>(bucket) * c.dt_s},
          {"hours", c.duration_s() / 3600}, {"t", numbers(t, 1)}, {"series", series}, {"metrics", metrics}};
}

// --- Where it fails -----------------------------------------------------------------------------

// One sensor's residual and measurement as 1 s means, one segment per cycle.
struct SensorSeries {
  const SensorDef* def = nullptr;
  Segments residual, measured;
  calibrate::NoiseSum noise;  // from the grid residual, at the sensor's own readings
};

// The 1 s means the statistics run on, one segment per cycle.
struct StatSeries {
  Segments speed, torque, airflow, ambient;
  std::vector<SensorSeries> sensors;  // those with at least one valid residual, in kSensors' order
  std::vector<double> t0_s;  // each segment's first time
};

StatSeries stat_series(const std::vector<CycleRun>& runs) {
  StatSeries s;
  for (const SensorDef& def : kSensors) s.sensors.push_back({&def, {}, {}, {}});
  for (const CycleRun& run : runs) {
    const data::Cycle& c = *run.cycle;
    const std::size_t block = steps_per_stat(c);
    for (SensorSeries& sensor : s.sensors) {
      sensor.residual.push_back(block_means(run.*(sensor.def->residual), block));
      sensor.measured.push_back(block_means(channel(c, sensor.def->measured), block));
      sensor.noise += calibrate::sensor_noise(run.*(sensor.def->residual), run.*(sensor.def->period));
    }
    s.speed.push_back(block_means(channel(c, Channel::speed_rpm), block));
    s.torque.push_back(block_means(channel(c, Channel::torque_nm), block));
    s.airflow.push_back(block_means(channel(c, Channel::airflow_m3s), block));
    s.ambient.push_back(block_means(channel(c, Channel::ambient_c), block));
    s.t0_s.push_back(c.t0_s);
  }
  std::erase_if(s.sensors, [](const SensorSeries& x) { return valid_count(x.residual) == 0; });
  return s;
}

std::vector<double> flat(const Segments& s) {
  std::vector<double> out;
  for (const auto& seg : s) out.insert(out.end(), seg.begin(), seg.end());
  return out;
}

json bins_json(const std::vector<Bin>& bins) {
  json a = json::array();
  for (const Bin& b : bins)
    a.push_back({{"lo", rounded(b.lo, 3)}, {"hi", rounded(b.hi, 3)}, {"n", b.n}, {"mean", number(b.mean)}, {"rmse", number(b.rmse)}});
  return a;
}

json region(const std::string& key, const std::string& label, const std::string& unit, const std::vector<double>& x, const std::vector<double>& e,
            const std::vector<double>& edges) {
  return {{"key", key}, {"label", label}, {"unit", unit}, {"bins", bins_json(bin_residuals(x, e, edges))}};
}

json speed_torque_map(const std::vector<double>& speed, const std::vector<double>& torque, const std::vector<double>& e) {
  const Range sr = valid_range(speed), tr = valid_range(torque);
  const auto x_edges = linear_edges(sr.lo, sr.hi, 8);
  const auto y_edges = linear_edges(std::isnan(tr.lo) ? 0 : tr.lo, std::isnan(tr.hi) ? 1 : tr.hi, 8);
  json cells = json::array();
  for (const auto& row : bin_residuals_2d(speed, torque, e, x_edges, y_edges)) cells.push_back(bins_json(row));
  return {{"speed_edges", numbers(x_edges, 0)}, {"torque_edges", numbers(y_edges, 0)}, {"cells", cells}};
}

json regions_json(const StatSeries& s, const SensorSeries& sensor) {
  const auto e = flat(sensor.residual);
  const auto speed = flat(s.speed), torque = flat(s.torque), airflow = flat(s.airflow), ambient = flat(s.ambient),
             temp = flat(sensor.measured);
  const Range ar = valid_range(airflow), am = valid_range(ambient), tm = valid_range(temp);
  return {{"speed_torque", speed_torque_map(speed, torque, e)},
          {"bands",
           {region("airflow", "airflow", "m³/s", airflow, e, linear_edges(ar.lo, ar.hi, 6)),
            region("ambient", "ambient", "°C", ambient, e, aligned_edges(am.lo, am.hi, 5)),
            region("temperature", std::string(sensor.def->label) + " (measured)", "°C", temp, e,
                   aligned_edges(tm.lo, tm.hi, 20))}},
          {"total", valid_count(sensor.residual)}};
}

json worst_json(const StatSeries& s, const Segments& residual, const std::vector<CycleRun>& runs) {
  json a = json::array();
  for (const Window& w : worst_windows(residual, kWindowS, kWindowStrideS, kWorstWindows)) {
    const double start = s.t0_s[w.segment] + static_cast<double>(w.start) * kStatStepS;
    a.push_back({{"cycle", runs[w.segment].cycle->name}, {"start_s", start},
                 {"end_s", start + static_cast<double>(w.length) * kStatStepS}, {"rmse_k", w.rmse}, {"n", w.n}});
  }
  return a;
}

json correlations_json(const StatSeries& s, const Segments& residual) {
  const std::size_t n = valid_count(residual);
  const auto acf_e = autocorrelation(residual, kMaxLagS);
  json cross = json::array();
  const std::pair<const char*, const Segments*> inputs[] = {
      {"speed", &s.speed}, {"torque", &s.torque}, {"airflow", &s.airflow}, {"ambient", &s.ambient}};
  for (const auto& [name, x] : inputs) {
    if (valid_count(*x) == 0) continue;
    cross.push_back({{"input", name}, {"r", numbers(cross_correlation(*x, residual, kMaxLagS), 4)},
                     {"band", bartlett_band(n, autocorrelation(*x, kMaxLagS), acf_e)}});
  }
  return {{"lag_step_s", kStatStepS}, {"max_lag_s", kMaxLagS}, {"n", n},
          {"acf", {{"r", numbers(acf_e, 4)}, {"band", white_noise_band(n)}}}, {"cross", cross}};
}

// RMSE (of the 1 s means) over the sensor's noise: 1 or below where the residual is the noise (1 s
// means of an interpolated sensor average some of it away), large where the model misses
// something. Sensors differ in noise, so the raw RMSE would not compare them.
double error_over_noise(const SensorSeries& sensor) {
  const double rmse = rms(sensor.residual), noise = sensor.noise.sigma();
  return noise > 0 ? rmse / noise : rmse;
}

json sensor_failures_json(const StatSeries& s, const SensorSeries& sensor, const std::vector<CycleRun>& runs) {
  return {{"sensor", sensor.def->key}, {"label", sensor.def->label}, {"rmse_k", number(rms(sensor.residual))},
          {"noise_k", number(sensor.noise.sigma())},
          {"error_over_noise", number(error_over_noise(sensor))}, {"regions", regions_json(s, sensor)},
          {"worst", worst_json(s, sensor.residual, runs)}, {"correlations", correlations_json(s, sensor.residual)}};
}

json failures_json(const StatSeries& s, const std::vector<CycleRun>& runs) {
  json sensors = json::array();
  const SensorSeries* worst = nullptr;
  for (const SensorSeries& sensor : s.sensors) {
    sensors.push_back(sensor_failures_json(s, sensor, runs));
    if (!worst || error_over_noise(sensor) > error_over_noise(*worst)) worst = &sensor;
  }
  // The page opens on the sensor the model fails most, so that a failure is seen without a click.
  return {{"sensors", sensors}, {"default_sensor", worst ? json(worst->def->key) : json(nullptr)}, {"window_s", kWindowS}};
}

// --- What is missing ----------------------------------------------------------------------------

// Which candidates get an evidence plot: the recommended one, then the significant ones, each
// group by statistic; never a drift or a sensor fault (findings about the data, with their own charts).
std::vector<SavedCandidate> leading(std::vector<SavedCandidate> c) {
  std::erase_if(c, [](const SavedCandidate& x) { return x.kind == "drift" || x.kind == "sensor"; });
  std::stable_sort(c.begin(), c.end(), [](const SavedCandidate& a, const SavedCandidate& b) {
    if (a.recommended != b.recommended) return a.recommended;
    if (a.significant != b.significant) return a.significant;
    return a.statistic > b.statistic;
  });
  if (c.size() > kLeadingCandidates) c.resize(kLeadingCandidates);
  return c;
}

// How far a residual's bin means move across the signature's bins (their spread about the pooled
// mean, weighted by count), over the sensor's noise: the sensor the effect shows on most.
double trend_over_noise(const std::vector<Bin>& bins, const SensorSeries& sensor) {
  double sum = 0, sum2 = 0;
  std::size_t n = 0;
  for (const Bin& b : bins) {
    if (b.n == 0) continue;
    sum += static_cast<double>(b.n) * b.mean;
    sum2 += static_cast<double>(b.n) * b.mean * b.mean;
    n += b.n;
  }
  if (n == 0) return 0;
  const double mean = sum / static_cast<double>(n);
  const double spread = std::sqrt(std::max(0.0, sum2 / static_cast<double>(n) - mean * mean));
  const double noise = sensor.noise.sigma();
  return noise > 0 ? spread / noise : spread;
}

// The residual of every sensor against the effect's signature, in the same bins: an effect that
// heats the rotor (windage) leaves the stator's residual flat and the rotor's rising.
json evidence_json(const SavedCandidate& cand, const CalibratedModel& cm, const std::vector<CycleRun>& runs,
                   const StatSeries& stats) {
  std::vector<double> sig;
  std::string label, unit;
  // The whole refit where diagnose gave it (the paper's parameters readjust beside the term), else
  // the candidate's own parameters on the calibration.
  std::vector<RefitValue> values;
  for (const auto& [name, value] : cand.refit_values.empty() ? cand.parameters : cand.refit_values)
    values.push_back({param_index(name), value});
  for (const CycleRun& run : runs) {
    // A library effect's own signature reads as physics; a term of the dictionary (or an effect
    // this build has none for) is shown by what it would change at diagnose's refit.
    auto s = cand.kind == "library" ? effect_signature(cand.effect, cm.model, cm.params, *run.cycle, run.sim)
                                    : std::nullopt;
    if (!s && !values.empty()) s = refit_signature(cand.effect, values, cm.model, cm.params, *run.cycle, run.sim);
    if (!s) return nullptr;
    label = s->label;
    unit = s->unit;
    const auto sm = block_means(s->values, steps_per_stat(*run.cycle));
    sig.insert(sig.end(), sm.begin(), sm.end());
  }
  const auto edges = quantile_edges(sig, kSignatureBins);
  json sensors = json::array();
  std::string most;
  double most_trend = -1;
  for (const SensorSeries& sensor : stats.sensors) {
    const auto bins = bin_residuals(sig, flat(sensor.residual), edges);
    const double trend = trend_over_noise(bins, sensor);
    sensors.push_back({{"sensor", sensor.def->key}, {"label", sensor.def->label}, {"trend_over_noise", trend},
                       {"bins", bins_json(bins)}});
    if (trend > most_trend) {
      most_trend = trend;
      most = sensor.def->key;
    }
  }
  return {{"effect", cand.effect}, {"kind", cand.kind}, {"words", cand.words}, {"label", label}, {"unit", unit},
          {"sensors", sensors}, {"most", most}};
}

json diagnosis_json(const std::optional<SavedDiagnosis>& d, const CalibratedModel& cm, const std::vector<CycleRun>& runs,
                    const StatSeries& stats) {
  if (!d) return nullptr;
  json candidates = json::array();
  for (const SavedCandidate& c : d->candidates)
    candidates.push_back({{"effect", c.effect}, {"kind", c.kind}, {"words", c.words}, {"verdict", c.verdict},
                          {"statistic", number(c.statistic)}, {"threshold", number(c.threshold)},
                          {"predicted_rmse_k", number(c.predicted_rmse_k)}, {"refit_rmse_k", number(c.refit_rmse_k)},
                          {"test_rmse_k_before", number(c.test_rmse_k_before)},
                          {"test_rmse_k_after", number(c.test_rmse_k_after)}, {"significant", c.significant},
                          {"recommended", c.recommended}});
  json evidence = json::array();
  for (const SavedCandidate& c : leading(d->candidates)) {
    json ev = evidence_json(c, cm, runs, stats);
    if (!ev.is_null()) evidence.push_back(std::move(ev));
  }
  return {{"rmse_k", number(d->rmse_k)}, {"candidates", candidates}, {"evidence", evidence},
          {"adequacy", d->adequacy}, {"drift", d->drift}, {"sensor_faults", d->sensor_faults}};
}

// --- History ------------------------------------------------------------------------------------

// Both sensors' residuals as one RMS, each sample counting once: sqrt((n_s e_s^2 + n_r e_r^2) /
// (n_s + n_r)). The figure a calibration's fit improves, whichever sensor it improves on.
json combined_rmse(const ErrorMetrics& stator, const ErrorMetrics& rotor) {
  const double ns = static_cast<double>(stator.samples), nr = static_cast<double>(rotor.samples);
  if (ns + nr == 0) return nullptr;
  double sum = ns * stator.rmse_k * stator.rmse_k;
  if (nr > 0) sum += nr * rotor.rmse_k * rotor.rmse_k;
  return number(std::sqrt(sum / (ns + nr)));
}

json history_entry(const std::filesystem::path& file, const calibrate::CalibrationResult& cal, bool current) {
  const bool test = !cal.test.cycles.empty();
  json e = {{"file", file.filename().string()}, {"created_utc", cal.created_utc}, {"method", cal.method},
            {"effects", effect_names(cal.effects)}, {"motor", cal.motor.name}, {"current", current},
            {"train_rmse_stator_k", number(cal.train.stator.rmse_k)},
            {"test_rmse_stator_k", test ? number(cal.test.stator.rmse_k) : json(nullptr)},
            {"train_rmse_combined_k", combined_rmse(cal.train.stator, cal.train.rotor)},
            {"test_rmse_combined_k", test ? combined_rmse(cal.test.stator, cal.test.rotor) : json(nullptr)}};
  if (cal.train.rotor.samples) e["train_rmse_rotor_k"] = cal.train.rotor.rmse_k;
  if (cal.test.rotor.samples) e["test_rmse_rotor_k"] = cal.test.rotor.rmse_k;
  return e;
}

// Every calibration JSON in `dir` by created_utc; other JSON files (a diagnosis, settings) are
// skipped, and counted, since a history directory is usually a working directory.
json history_json(const std::filesystem::path& dir, const std::filesystem::path& current) {
  std::vector<std::pair<std::string, json>> entries;
  std::size_t skipped = 0;
  std::error_code ec;
  for (const auto& f : std::filesystem::directory_iterator(dir, ec)) {
    if (!f.is_regular_file() || f.path().extension() != ".json") continue;
    try {
      const calibrate::CalibrationResult cal = calibrate::load_calibration(f.path());
      entries.emplace_back(cal.created_utc + f.path().filename().string(),
                           history_entry(f.path(), cal, std::filesystem::equivalent(f.path(), current, ec)));
    } catch (const std::exception&) {
      ++skipped;
    }
  }
  std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  json runs = json::array();
  for (auto& [key, e] : entries) runs.push_back(std::move(e));
  return {{"dir", dir.string()}, {"runs", runs}, {"skipped", skipped}};
}

// Where the data is not the calibration's own: which cycles it never saw and lptn check's verdict
// on them (null for the calibration's own data).
json check_json(const calibrate::CalibrationResult& cal, const data::Dataset& ds, const check::Provenance& provenance,
                const std::optional<MotorFile>& data_motor) {
  if (provenance.all_seen()) return nullptr;
  const check::Check c = check::check(cal, ds, data_motor, hostio::worker_threads());
  json j = check::to_json(c);
  return {{"holds", j["holds"]}, {"reasons", j["reasons"]}, {"summary", provenance.summary()},
          {"never_seen", j["data"]["never_seen"]}, {"cycles", j["cycles"]}, {"thresholds", j["thresholds"]},
          {"cooling_factor", j["cooling_factor"]}};
}

// The calibration's warnings in words, for the page to list under its status.
json warning_messages(const calibrate::CalibrationResult& cal) {
  json out = json::array();
  for (const calibrate::CalibrationWarning& w : cal.warnings) out.push_back(w.message);
  return out;
}

json meta_json(const ReportOptions& o, const calibrate::CalibrationResult& cal, const data::Dataset& ds) {
  double hours = 0;
  for (const auto& c : ds.cycles) hours += c.duration_s() / 3600;
  return {{"calibration", o.calibration.string()}, {"data", o.data.string()}, {"method", cal.method},
          {"created_utc", cal.created_utc}, {"motor", cal.motor.name}, {"effects", effect_names(cal.effects)},
          // A calibration that is not ok says so at the top of the page, as lptn replay says it.
          {"status", cal.status}, {"status_caution", calibrate::status_caution(cal, o.calibration.string(), true)},
          {"warnings", warning_messages(cal)},
          {"cycles", ds.cycles.size()}, {"hours", hours}, {"generated_utc", hostio::utc_now()},
          {"train_rmse_stator_k", number(cal.train.stator.rmse_k)},
          {"test_rmse_stator_k", cal.test.cycles.empty() ? json(nullptr) : number(cal.test.stator.rmse_k)},
          {"train_rmse_rotor_k", cal.train.rotor.samples ? number(cal.train.rotor.rmse_k) : json(nullptr)},
          {"test_rmse_rotor_k", cal.test.rotor.samples ? number(cal.test.rotor.rmse_k) : json(nullptr)}};
}

}  // namespace

nlohmann::json report_data(const ReportOptions& o, const std::function<void(const std::string&)>& progress) {
  if (o.data.empty() && o.calibration.empty()) {
    if (o.fleet.empty()) throw ReportInputError("report: give --data and --calibration, or --fleet");
    return {{"fleet", fleet_section(o.fleet)}, {"generated_utc", hostio::utc_now()}};
  }
  const json fleet = o.fleet.empty() ? json(nullptr) : fleet_section(o.fleet);  // bad input fails fast
  const calibrate::CalibrationResult cal = calibrate::load_calibration(o.calibration);
  std::optional<SavedDiagnosis> diagnosis;
  if (!o.diagnosis.empty()) diagnosis = diagnose::load_diagnosis(o.diagnosis);  // before the long part: bad input fails fast
  const CalibratedModel cm = calibrated_model(cal);
  data::LoadOptions load;
  if (!o.data_map.empty()) load.map = std::make_shared<const data::DataMap>(data::load_data_map(o.data_map));
  data::Dataset ds = data::load_fleet_dump({o.data}, load);
  const std::vector<std::string> corrections = check::correct_as_calibrated(ds, cal);
  for (const std::string& c : corrections) progress(c);
  const std::optional<MotorFile> data_motor = check::motor_beside({o.data.string()});
  const check::Provenance provenance = check::provenance(cal, ds, data_motor);

  std::vector<CycleRun> runs;
  json cycles = json::array();
  for (const data::Cycle& cycle : ds.cycles) {
    progress("cycle " + std::to_string(runs.size() + 1) + "/" + std::to_string(ds.cycles.size()) + " " + cycle.name);
    runs.push_back(run_cycle_model(cm, cycle, role_of(provenance.cycles[runs.size()])));
    runs.back().stator_period = calibrate::reading_period(ds, cycle, Channel::stator_winding_c);
    runs.back().rotor_period = calibrate::reading_period(ds, cycle, Channel::rotor_c);
    cycles.push_back(compare_cycle(runs.back()));
  }
  progress("statistics");
  json checked = nullptr;
  if (!provenance.all_seen()) {
    progress("lptn check: data this calibration never saw");
    checked = check_json(cal, ds, provenance, data_motor);
  }
  const StatSeries stats = stat_series(runs);
  const std::filesystem::path history = o.history.empty() ? std::filesystem::absolute(o.calibration).parent_path() : o.history;
  json meta = meta_json(o, cal, ds);
  meta["sensor_corrections"] = corrections;
  return {{"meta", meta}, {"check", checked}, {"cycles", cycles}, {"failures", failures_json(stats, runs)},
          {"diagnosis", diagnosis_json(diagnosis, cm, runs, stats)}, {"history", history_json(history, o.calibration)},
          {"fleet", fleet}, {"generated_utc", hostio::utc_now()}};
}

}  // namespace lptn::report
