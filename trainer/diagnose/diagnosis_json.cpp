// The diagnosis as JSON (lptn diagnose --json).
#include <cmath>
#include <string>

#include "trainer/diagnose/diagnose.hpp"
#include "trainer/diagnose/internal/json_number.hpp"

namespace lptn::diagnose {
namespace {

using internal::json_number;

// The candidate's reason: why it is not distinguishable, not significant or failed; for a significant
// one, why it is not recommended (empty for the recommendation).
std::string reason(const Candidate& c, const Diagnosis& d, const Candidate* best) {
  if (c.verdict != Verdict::significant || best == &c) return c.reason;
  std::string why = d.not_recommended_because(c);
  if (why.empty() && best) why = "ranked after " + best->name + " (one recommendation per diagnosis)";
  return why;
}

nlohmann::json to_json(const Candidate& c, const Diagnosis& d) {
  nlohmann::json params = nlohmann::json::object();
  for (int i = 0; i < kNumParams; ++i)
    if (effect_of_param(i) == c.effect)
      params[std::string(param_spec(i).name)] = {{"value", c.refit.values[i]}, {"std_error", json_number(c.refit.std_error[i])},
                                                 {"unit", std::string(param_spec(i).unit)}};
  // Every parameter as the refit left it (the paper's readjust too): what lptn report simulates to
  // show what the refit changes in each sensor's reading.
  nlohmann::json values = nlohmann::json::object();
  for (int i = 0; i < kNumParams; ++i) values[std::string(param_spec(i).name)] = c.refit.values[i];
  nlohmann::json starts = nlohmann::json::array();
  for (const RefitStart& s : c.starts)
    starts.push_back({{"from", s.from}, {"rmse_k", json_number(s.rmse_k)}, {"iterations", s.iterations},
                      {"converged", s.converged}, {"coarse_grid_only", s.coarse_only}, {"error", s.error}});
  const Candidate* best = d.best();
  nlohmann::json j = {{"effect", c.name},
          {"statistic", c.statistic},
          {"threshold", c.threshold},
          {"df", c.df},
          {"score", c.score},
          {"predicted_rmse_k", c.predicted_rmse_k},
          {"refit_rmse_k", json_number(c.refit_rmse_k)},
          {"train_stator_rmse_k", json_number(c.train_stator_rmse_k)},
          {"test_stator_rmse_k", json_number(c.test_stator_rmse_k)},
          {"significant", c.verdict == Verdict::significant},
          {"kind", c.kind == EffectKind::term ? "term" : "library"},
          {"words", c.words},
          {"blocks", c.blocks},
          {"block_gain", c.block_gain},
          {"block_t", json_number(c.block_t)},
          {"block_threshold", c.block_threshold},
          {"recommended", best == &c},
          {"pinned", pinned(c)},
          {"test_rmse_k_before", json_number(d.test_rmse_k)},
          {"test_rmse_k_after", json_number(c.test_rmse_k_after)},
          {"verdict", to_string(c.verdict)},
          {"reason", reason(c, d, best)},
          {"needs", c.needs},
          {"parameters", params},
          {"refit_values", values},
          {"refit_iterations", c.refit.iterations},
          {"refit_converged", c.refit.converged},
          {"refit_seconds", c.refit.seconds},
          {"refit_start", c.start},
          {"refit_starts", starts}};
  if (c.kind == EffectKind::term) {
    j["node"] = c.node;
    j["formula"] = c.formula;
  }
  return j;
}

// A drift is listed among the candidates (kind "drift") so that a reader of the list sees it, but
// it is a finding about the data, never an effect to add.
nlohmann::json drift_candidate(const Diagnosis& d) {
  return {{"effect", std::string("drift_") + to_string(d.drift.group)},
          {"kind", "drift"},
          {"significant", true},
          {"recommended", false},
          {"verdict", "drift"},
          {"cycles", d.drift.cycles},
          {"words", d.drift.finding},
          {"reason", d.drift.finding},
          {"needs", d.drift.inspect},
          {"p_value", d.drift.p_value},
          {"change", d.drift.change},
          {"test_rmse_k_before", json_number(d.test_rmse_k)},
          {"test_rmse_k_after", json_number(d.test_rmse_k)}};
}

// A sensor fault likewise (kind "sensor"): a finding about the data's sensor, never recommended.
nlohmann::json sensor_candidate(const Diagnosis& d, const SensorFinding& s) {
  return {{"effect", std::string("sensor_") + data::sensor_name(s.sensor) + "_" + data::to_string(s.fault.shape)},
          {"kind", "sensor"},
          {"sensor", data::sensor_name(s.sensor)},
          {"shape", data::to_string(s.fault.shape)},
          {"size", s.fault.size},
          {"size_k", s.size_k},
          {"cycles", s.cycles},
          {"significant", true},
          {"recommended", false},
          {"verdict", "sensor fault"},
          {"words", s.finding},
          {"reason", s.finding},
          {"needs", s.inspect},
          {"calibrate", s.calibrate},
          {"p_value", s.p_value},
          {"test_rmse_k_before", json_number(d.test_rmse_k)},
          {"test_rmse_k_after", json_number(d.test_rmse_k)}};
}

}  // namespace

nlohmann::json to_json(const Diagnosis& d) {
  nlohmann::json candidates = nlohmann::json::array();
  for (const Candidate& c : d.candidates) candidates.push_back(to_json(c, d));
  if (const SensorFinding* s = d.sensor_fault()) candidates.push_back(sensor_candidate(d, *s));
  if (d.drift.found) candidates.push_back(drift_candidate(d));
  nlohmann::json j = to_json(d.adequacy);  // "adequate" and "sensors" first: the verdict on the model itself
  j["format_version"] = kDiagnosisFormatVersion;
  j["rmse_k"] = d.rmse_k;
  j["test_rmse_k"] = json_number(d.test_rmse_k);
  j["correlation_time_steps"] = d.baseline.correlation_time;
  j["candidates"] = candidates;
  j["drift"] = to_json(d.drift);
  // Not "sensors": that is the adequacy's, per sensor, above.
  j["sensor_faults"] = nlohmann::json::array();
  for (const SensorFinding& s : d.sensors) j["sensor_faults"].push_back(to_json(s));
  nlohmann::json scores = nlohmann::json::array();
  for (const Diagnosis::TermScore& t : d.term_scores)
    scores.push_back({{"term", t.name}, {"score", t.score}, {"feasible", t.feasible}});
  j["term_scores"] = scores;
  return j;
}

}  // namespace lptn::diagnose
