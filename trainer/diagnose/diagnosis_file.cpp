#include "trainer/diagnose/diagnosis_file.hpp"

#include <cmath>

#include "hostio/json_file.hpp"
#include "trainer/diagnose/diagnose.hpp"
#include "trainer/diagnose/internal/json_number.hpp"

namespace lptn::diagnose {
namespace {

using nlohmann::json;

double number_or_nan(const json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : std::nan("");
}

std::string string_or(const json& j, const char* key, const char* fallback) {
  const auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : fallback;
}

SavedCandidate parse_candidate(const json& j, const std::string& where) {
  if (!j.is_object() || !j.contains("effect") || !j["effect"].is_string())
    throw DiagnosisFileError(where + ": expected an object with a string 'effect'");
  SavedCandidate c;
  c.effect = j["effect"].get<std::string>();
  c.kind = string_or(j, "kind", "library");
  c.words = string_or(j, "words", "");
  c.verdict = string_or(j, "verdict", "");
  c.statistic = number_or_nan(j, "statistic");
  c.threshold = number_or_nan(j, "threshold");
  c.predicted_rmse_k = number_or_nan(j, "predicted_rmse_k");
  c.refit_rmse_k = number_or_nan(j, "refit_rmse_k");
  c.test_rmse_k_before = number_or_nan(j, "test_rmse_k_before");
  c.test_rmse_k_after = number_or_nan(j, "test_rmse_k_after");
  c.significant = j.value("significant", false);
  c.recommended = j.value("recommended", false);
  const auto named_values = [&](const char* key, std::vector<std::pair<std::string, double>>& out, bool nested) {
    const auto p = j.find(key);
    if (p == j.end() || !p->is_object()) return;
    for (const auto& [name, v] : p->items()) {
      const double value = nested ? (v.is_object() ? number_or_nan(v, "value") : std::nan(""))
                                  : (v.is_number() ? v.get<double>() : std::nan(""));
      if (!std::isfinite(value))
        throw DiagnosisFileError(where + ": " + key + "." + name + (nested ? ": expected {\"value\": number}" : ": expected a number"));
      out.emplace_back(name, value);
    }
  };
  named_values("parameters", c.parameters, true);
  named_values("refit_values", c.refit_values, false);
  return c;
}

}  // namespace

SavedDiagnosis load_diagnosis(const std::filesystem::path& path) {
  const std::string shown = path.string();
  const std::string text = hostio::read_text_file(path);  // JsonFileError "FILE: cannot read (...)", bad input too
  json j;
  try {
    j = hostio::parse_json_text(text, shown);
  } catch (const hostio::JsonFileError& e) {
    // "FILE: line N: reason" -> "FILE: not JSON (...): line N: reason"
    throw DiagnosisFileError(shown + ": not JSON (expected `lptn diagnose --json` output): " +
                             std::string(e.what()).substr(shown.size() + 2));
  }
  if (!j.is_object() || !j.contains("candidates") || !j["candidates"].is_array())
    throw DiagnosisFileError(path.string() + ": no 'candidates' array (expected `lptn diagnose --json` output)");
  // Format 1 (no format_version) predates the sensor check: it is read, without sensor findings.
  if (j.contains("format_version")) {
    const json& v = j["format_version"];
    if (!v.is_number_integer() || v.get<int>() < 1 || v.get<int>() > kDiagnosisFormatVersion)
      throw DiagnosisFileError(path.string() + ": format_version " + v.dump() + ", this lptn reads diagnosis files of format 1 to " +
                             std::to_string(kDiagnosisFormatVersion) + " (a newer lptn wrote it)");
  }
  SavedDiagnosis d;
  d.rmse_k = number_or_nan(j, "rmse_k");
  if (j.contains("adequate") && j["adequate"].is_boolean() && j.contains("sensors") && j["sensors"].is_object())
    d.adequacy = {{"adequate", j["adequate"]}, {"adequate_within", internal::json_number(number_or_nan(j, "adequate_within"))},
                  {"sensors", j["sensors"]}};
  if (j.contains("drift") && j["drift"].is_object()) d.drift = j["drift"];
  if (j.contains("sensor_faults") && j["sensor_faults"].is_array()) d.sensor_faults = j["sensor_faults"];
  for (std::size_t i = 0; i < j["candidates"].size(); ++i)
    d.candidates.push_back(parse_candidate(j["candidates"][i], path.string() + ": candidates[" + std::to_string(i) + "]"));
  return d;
}

}  // namespace lptn::diagnose
