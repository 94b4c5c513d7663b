#include "trainer/diagnose/adequacy.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <thread>
#include <utility>

#include "hostio/worker_threads.hpp"
#include "trainer/calibrate/sensor_noise.hpp"
#include "trainer/diagnose/internal/json_number.hpp"
#include "trainer/diagnose/internal/sensor_traces.hpp"
#include "trainer/diagnose/internal/where.hpp"

namespace lptn::diagnose {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using internal::kSensorTraces;

// One cycle's contribution per sensor: its metrics and the noise sums of its residual.
struct CycleFinding {
  calibrate::CycleMetrics metrics;
  calibrate::NoiseSum noise[2];
  internal::WhereSums where[2];
};

CycleFinding examine(const Model<double>& model, const ParamVector<double>& params, calibrate::DatasetRef dataset,
                     const data::Cycle& cycle, const internal::RegionEdges& edges) {
  calibrate::CycleEvaluation e = calibrate::simulate_and_evaluate(model, params, cycle);
  CycleFinding f;
  f.metrics = std::move(e.metrics);
  for (int s = 0; s < 2; ++s) {
    if (!cycle.has(kSensorTraces[s].channel)) continue;
    const std::vector<float>& m = e.simulation.*(kSensorTraces[s].trace);
    std::vector<float> r(cycle.steps);
    for (std::size_t k = 0; k < cycle.steps; ++k) r[k] = m[k] - cycle.at(kSensorTraces[s].channel, k);
    f.noise[s] = calibrate::sensor_noise(r, calibrate::reading_period(dataset.data, cycle, kSensorTraces[s].channel));
    f.where[s] = internal::where_sums(cycle, kSensorTraces[s].channel, r, edges);
  }
  return f;
}

std::vector<CycleFinding> examine_all(const Model<double>& model, const ParamVector<double>& params,
                                      calibrate::DatasetRef dataset, const std::vector<std::size_t>& cycles,
                                      const internal::RegionEdges& edges, int threads) {
  std::vector<CycleFinding> out(cycles.size());
  hostio::parallel_for(cycles.size(), threads,
               [&](std::size_t i) { out[i] = examine(model, params, dataset, dataset.cycles[cycles[i]], edges); });
  return out;
}

// The cycles' metrics as evaluate_split pools them.
calibrate::SplitMetrics split_metrics(std::vector<CycleFinding>::const_iterator from, std::vector<CycleFinding>::const_iterator to) {
  calibrate::SplitMetrics m;
  for (auto f = from; f != to; ++f) m.cycles.push_back(f->metrics);
  calibrate::pool_cycles(m);
  return m;
}

const ErrorMetrics& metric(const calibrate::CycleMetrics& m, int s) { return s == 0 ? m.stator : m.rotor; }

}  // namespace

Adequacy assess_adequacy(const Model<double>& model, const ParamVector<double>& params, calibrate::DatasetRef dataset,
                         const calibrate::Split& split, int threads) {
  std::vector<std::size_t> every = split.train;
  every.insert(every.end(), split.test.begin(), split.test.end());
  const internal::RegionEdges edges = internal::region_edges(dataset.data, every);
  // Train and test in one loop over the cores (a few cycles keep both busy only together).
  std::vector<CycleFinding> train = examine_all(model, params, dataset, every, edges, threads);
  const std::vector<CycleFinding> test(std::make_move_iterator(train.begin() + static_cast<std::ptrdiff_t>(split.train.size())),
                                       std::make_move_iterator(train.end()));
  train.resize(split.train.size());
  Adequacy a;
  a.train = split_metrics(train.begin(), train.end());
  a.test = split_metrics(test.begin(), test.end());
  for (int s = 0; s < 2; ++s) {
    // The noise is the sensor's, not the split's: pooled over every cycle.
    calibrate::NoiseSum noise;
    internal::WhereSums where;
    std::vector<ErrorMetrics> train_m, test_m;
    for (const CycleFinding& f : train) {
      noise += f.noise[s];
      where += f.where[s];
      if (metric(f.metrics, s).samples) train_m.push_back(metric(f.metrics, s));
    }
    for (const CycleFinding& f : test) {
      noise += f.noise[s];
      where += f.where[s];
      if (metric(f.metrics, s).samples) test_m.push_back(metric(f.metrics, s));
    }
    if (train_m.empty() && test_m.empty()) continue;  // not measured
    SensorAdequacy v;
    v.sensor = kSensorTraces[s].name;
    v.noise_k = noise.sigma();
    v.train_rmse_k = train_m.empty() ? kNaN : pool(train_m).rmse_k;
    v.test_rmse_k = test_m.empty() ? kNaN : pool(test_m).rmse_k;
    const double bound = kAdequateRatio * v.noise_k;
    const double worst = std::max(std::isnan(v.train_rmse_k) ? 0.0 : v.train_rmse_k,
                                  std::isnan(v.test_rmse_k) ? 0.0 : v.test_rmse_k);
    v.unexplained = worst > 0 ? std::max(0.0, 1 - v.noise_k * v.noise_k / (worst * worst)) : 0.0;
    v.adequate = !(worst > bound);  // a NaN noise (too few readings) judges nothing
    v.where = internal::where(where, edges);
    v.shape = internal::shape(where);
    std::vector<std::pair<double, std::string>> beyond;
    const std::vector<CycleFinding>* sides[] = {&train, &test};
    for (const std::vector<CycleFinding>* side : sides)
      for (const CycleFinding& f : *side)
        if (metric(f.metrics, s).samples && metric(f.metrics, s).rmse_k > bound)
          beyond.emplace_back(metric(f.metrics, s).rmse_k, f.metrics.name);
    std::sort(beyond.begin(), beyond.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
    for (const auto& b : beyond) v.cycles.push_back(b.second);
    a.adequate = a.adequate && v.adequate;
    a.sensors.push_back(std::move(v));
  }
  return a;
}

nlohmann::json to_json(const Adequacy& adequacy) {
  const auto number = internal::json_number;
  nlohmann::json sensors = nlohmann::json::object();
  for (const SensorAdequacy& s : adequacy.sensors) {
    const double worst = std::max(std::isnan(s.train_rmse_k) ? 0.0 : s.train_rmse_k,
                                  std::isnan(s.test_rmse_k) ? 0.0 : s.test_rmse_k);
    sensors[s.sensor] = {{"rmse_k", number(worst)},          {"noise_k", number(s.noise_k)},
                         {"adequate", s.adequate},           {"train_rmse_k", number(s.train_rmse_k)},
                         {"test_rmse_k", number(s.test_rmse_k)}, {"unexplained", number(s.unexplained)},
                         {"cycles", s.cycles}};
    nlohmann::json follows = nlohmann::json::array();
    for (const Follows& f : s.where.follows) follows.push_back({{"input", f.input}, {"correlation", f.correlation}});
    sensors[s.sensor]["follows"] = follows;
    sensors[s.sensor]["region"] =
        s.where.region.empty() ? nlohmann::json(nullptr)
                               : nlohmann::json{{"name", s.where.region}, {"rmse_k", s.where.region_rmse_k},
                                                {"share", s.where.region_share}};
    sensors[s.sensor]["shape"] = {{"correlation_time_s", number(s.shape.correlation_time_s)},
                                  {"correlation_time_at_least", s.shape.correlation_time_at_least},
                                  {"mean_k", number(s.shape.mean_k)},
                                  {"with_warming", number(s.shape.with_warming)},
                                  {"with_rise", number(s.shape.with_rise)},
                                  {"effective_readings", number(s.shape.effective_readings)},
                                  {"words", shape_in_words(s)}};
  }
  return {{"adequate", adequacy.adequate}, {"adequate_within", kAdequateRatio}, {"sensors", sensors}};
}

namespace {

// "; largest at high speed (..), low current (..): 3.10 K; follows speed (r = -0.81), airflow (r = +0.42)"
std::string where_words(const Where& w) {
  std::string out;
  char part[160];
  if (!w.region.empty()) {
    std::snprintf(part, sizeof part, "; largest at %s: %.2f K", w.region.c_str(), w.region_rmse_k);
    out += part;
  }
  for (std::size_t i = 0; i < w.follows.size(); ++i) {
    std::snprintf(part, sizeof part, "%s%s (r = %+.2f)", i ? ", " : "; follows ", w.follows[i].input.c_str(),
                  w.follows[i].correlation);
    out += part;
  }
  return out;
}

std::string minutes(double seconds) {
  char s[32];
  if (seconds < 90)
    std::snprintf(s, sizeof s, "%.0f s", seconds);
  else
    std::snprintf(s, sizeof s, "%.0f min", seconds / 60);
  return s;
}

// What a residual that follows an input says, by the input: its sign is model - measured.
std::string input_words(const Follows& f) {
  const bool too_cold = f.correlation < 0;  // the model falls behind as the input rises
  if (f.input == "airflow")
    return too_cold ? "the model cools too well as the airflow rises: a cooling that grows less with airflow than "
                      "modelled"
                    : "the model is too hot when the airflow is high: a cooling that grows more with airflow than "
                      "modelled";
  if (f.input == "ambient")
    return too_cold ? "the model falls behind as the ambient rises: the cooling air warms on its way (recirculation, "
                      "a warmer intake), or a heat source that grows with ambient"
                    : "the model runs ahead as the ambient rises: the cooling air is cooler than the ambient sent";
  return too_cold ? "heat that grows with " + f.input + " is missing, or the model's share of it is too small"
                  : "the model puts too much heat with " + f.input + ", or a cooling that grows with " + f.input +
                        " is missing";
}

}  // namespace

double least_telling_correlation(const Shape& shape) {
  return std::max(internal::kFollowMin, 2 / std::sqrt(std::max(shape.effective_readings, 1.0)));
}

std::string shape_in_words(const SensorAdequacy& s) {
  if (s.adequate || !std::isfinite(s.shape.correlation_time_s)) return "";
  const Shape& sh = s.shape;
  char part[256];
  std::snprintf(part, sizeof part, "the %s residual (model - measured) averages %+.2f K and stays correlated for %s%s",
                s.sensor.c_str(), sh.mean_k, sh.correlation_time_at_least ? "more than " : "",
                minutes(sh.correlation_time_s).c_str());
  std::string out = part;
  // Faster than any node (the winding's time constant is minutes): the sensor's doing.
  if (sh.correlation_time_s < kFastResidualS)
    return out + ": faster than any node of the model, so not the motor's heat: the sensor's own dynamics (a lag, a "
                 "filter, a slow sampling) or interference on its line";
  const double follow_min = least_telling_correlation(sh);
  const Follows* input = s.where.follows.empty() ? nullptr : &s.where.follows.front();
  const double input_r = input ? std::abs(input->correlation) : 0;
  if (std::abs(sh.with_warming) >= follow_min && std::abs(sh.with_warming) >= input_r) {
    std::snprintf(part, sizeof part, "; it follows the sensor's own rate of warming (r = %+.2f)", sh.with_warming);
    out += part;
    // Either sign has two readings: a calibration absorbs what its parameters can, so the phase
    // left over does not tell a missing store from a missing source by itself.
    return out + (sh.with_warming > 0
                      ? ": the model warms and cools faster than the motor: heat stored where the model has no mass "
                        "(a frame, a housing: a thermal mass, mass_* in the dictionary), or heat the model puts on "
                        "this side while loaded that the motor does not have"
                      : ": the model warms more slowly than the motor under load: a heat source on this side the "
                        "model lacks, or a capacity larger than the motor's");
  }
  if (input && input_r >= follow_min) {
    std::snprintf(part, sizeof part, "; it follows %s (r = %+.2f, through a %.0f-min lag): ", input->input.c_str(),
                  input->correlation, internal::kFollowTauS / 60);
    return out + part + input_words(*input);
  }
  if (std::abs(sh.with_rise) >= follow_min) {
    std::snprintf(part, sizeof part, "; it follows the sensor's rise over ambient (r = %+.2f)", sh.with_rise);
    out += part;
    return out + (sh.with_rise < 0 ? ": the model falls behind as the motor gets hot: a loss that grows with "
                                     "temperature, or a cooling that weakens when hot"
                                   : ": the model runs ahead as the motor gets hot: a cooling that grows with "
                                     "temperature (free convection, radiation) is missing");
  }
  // Nothing beyond chance. Say what is strongest all the same, and where the residual is largest:
  // with few independent samples a real cause can stay under the bar (a rotor loss growing as
  // speed^3 where the model has speed^2: r = -0.46 with speed on 7 samples, largest at top speed).
  std::snprintf(part, sizeof part,
                "; nothing it was compared with (the inputs, its warming, its temperature) follows it beyond chance "
                "(|r| < %.2f on its %.0f independent samples",
                follow_min, sh.effective_readings);
  out += part;
  if (input) {
    std::snprintf(part, sizeof part, "; the strongest, %s at r = %+.2f, would need more cycles", input->input.c_str(),
                  input->correlation);
    out += part;
  }
  out += ")";
  if (!s.where.region.empty()) {
    std::snprintf(part, sizeof part, "; it is largest at %s (%.2f K)", s.where.region.c_str(), s.where.region_rmse_k);
    out += part;
  }
  return out + (sh.correlation_time_s >= kSlowResidualS
                    ? ": a slow mode the model lacks (heat stored in a mass it does not have: mass_* in the "
                      "dictionary; a cooling that changes within the cycles), or a cause these samples cannot show"
                    : ": compare its cycles and operating regions in lptn report");
}

std::string describe(const SensorAdequacy& s) {
  const bool test_worse = !std::isnan(s.test_rmse_k) && s.test_rmse_k >= s.train_rmse_k;
  const double rmse = test_worse ? s.test_rmse_k : s.train_rmse_k;
  char line[256];
  std::snprintf(line, sizeof line, "%s: %s RMSE %.3f K = %.1fx its noise of %.3f K (estimated from its readings): %s",
                s.sensor.c_str(), test_worse ? "test" : "train", rmse, rmse / s.noise_k, s.noise_k,
                s.adequate ? "adequate" : "something is missing");
  std::string out = line;
  if (!s.adequate && !s.cycles.empty()) {
    out += " (worst: ";
    for (std::size_t i = 0; i < s.cycles.size() && i < 4; ++i) out += (i ? ", " : "") + s.cycles[i];
    out += s.cycles.size() > 4 ? ", ...)" : ")";
  }
  if (!s.adequate) out += where_words(s.where);
  return out;
}

}  // namespace lptn::diagnose
