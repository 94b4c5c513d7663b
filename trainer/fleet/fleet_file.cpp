#include "trainer/fleet/fleet_file.hpp"

#include <cmath>
#include <stdexcept>

#include "hostio/atomic_file.hpp"

namespace lptn {

nlohmann::ordered_json fleet_json(const CalibrationResult& pooled, const FleetFit& fit, const FleetSettings& settings) {
  nlohmann::ordered_json j;
  j["format_version"] = kFleetFormatVersion;
  j["pooled"] = nlohmann::ordered_json::parse(to_json(pooled).dump());  // keeps calibration.json's key order
  nlohmann::ordered_json& f = j["fleet"];
  f["motors"] = fit.motors.size();
  f["method"] =
      "hierarchical by alternation: the shared parameters by LM over every motor's training cycles, each motor's "
      "cooling factor against them, normalized to the median motor";
  f["rounds"] = fit.rounds;
  f["log_cooling_factor_spread"] = fit.log_factor_spread;
  f["seconds"] = fit.seconds;
  f["outlier_test"] = {
      {"method", "leave-one-out Student t on ln(cooling factor), Bonferroni over the motors"},
      {"family_alpha", settings.family_alpha},
      {"threshold_t", fit.motors.size() >= static_cast<std::size_t>(kMinMotorsForOutlierTest)
                          ? nlohmann::ordered_json(outlier_threshold(static_cast<int>(fit.motors.size()), settings.family_alpha))
                          : nlohmann::ordered_json(nullptr)}};
  nlohmann::ordered_json& motors = j["motors"];
  motors = nlohmann::ordered_json::object();
  for (const FleetMotorResult& m : fit.motors) {
    nlohmann::ordered_json o;
    o["cooling_factor"] = m.cooling_factor;
    o["cooling_factor_std"] = m.cooling_factor_std;
    o["outlier"] = m.verdict.outlier;
    o["reason"] = m.verdict.reason;
    o["t"] = m.verdict.tested ? nlohmann::ordered_json(m.verdict.t) : nlohmann::ordered_json(nullptr);
    o["cycles"] = m.metrics.cycles.size();
    o["metrics"] = split_metrics_json(m.metrics);
    o["parameters"] = nlohmann::ordered_json::array();
    for (int i = 0; i < kNumParams; ++i)
      o["parameters"].push_back({{"name", std::string(param_spec(i).name)},
                                 {"unit", std::string(param_spec(i).unit)},
                                 {"value", m.parameters[static_cast<std::size_t>(i)]}});
    motors[m.id] = o;
  }
  return j;
}

void save_fleet(const std::filesystem::path& path, const CalibrationResult& pooled, const FleetFit& fit,
                const FleetSettings& settings) {
  write_file_atomically(path, fleet_json(pooled, fit, settings).dump(2) + "\n");
}

namespace {

[[noreturn]] void bad(const std::string& file, const std::string& field, const std::string& why) {
  throw CalibrationFileError(file + ": field '" + field + "': " + why);
}

double number(const nlohmann::json& j, const std::string& file, const std::string& field) {
  if (!j.is_number()) bad(file, field, j.is_null() ? "missing" : "not a number");
  const double v = j.get<double>();
  if (!std::isfinite(v)) bad(file, field, "not finite");
  return v;
}

}  // namespace

FleetFile load_fleet_file(const std::filesystem::path& path) {
  const std::string shown = path.string();
  const nlohmann::json j = read_json_file(path);
  if (j.is_object() && j.contains("parameters") && j.contains("motor") && !j.contains("pooled"))
    throw CalibrationFileError(shown + ": a single motor's calibration (calibration.json), not a fleet calibration: give "
                                       "it as --calibration");
  if (!j.is_object() || !j.contains("format_version")) bad(shown, "format_version", "missing: is this a fleet.json?");
  if (j["format_version"] != kFleetFormatVersion)
    bad(shown, "format_version", "version " + j["format_version"].dump() + ", this lptn reads " +
                                     std::to_string(kFleetFormatVersion));
  if (!j.contains("pooled")) bad(shown, "pooled", "missing");
  FleetFile out;
  out.pooled = calibration_from_json(j["pooled"], shown + " (pooled)");
  if (!j.contains("fleet") || !j["fleet"].is_object()) bad(shown, "fleet", "missing or not an object");
  const nlohmann::json& f = j["fleet"];
  out.rounds = static_cast<int>(number(f.value("rounds", nlohmann::json()), shown, "fleet.rounds"));
  if (!f.contains("outlier_test") || !f["outlier_test"].is_object()) bad(shown, "fleet.outlier_test", "missing");
  out.family_alpha = number(f["outlier_test"].value("family_alpha", nlohmann::json()), shown, "fleet.outlier_test.family_alpha");
  if (f["outlier_test"].contains("threshold_t") && !f["outlier_test"]["threshold_t"].is_null())
    out.threshold_t = number(f["outlier_test"]["threshold_t"], shown, "fleet.outlier_test.threshold_t");
  if (!j.contains("motors") || !j["motors"].is_object()) bad(shown, "motors", "missing or not an object");
  for (const auto& [id, m] : j["motors"].items()) {
    const std::string at = "motors." + id;
    FleetFileMotor motor;
    motor.id = id;
    motor.parameters = out.pooled.values();
    if (!m.is_object()) bad(shown, at, "not an object");
    motor.cooling_factor = number(m.value("cooling_factor", nlohmann::json()), shown, at + ".cooling_factor");
    motor.cooling_factor_std = number(m.value("cooling_factor_std", nlohmann::json()), shown, at + ".cooling_factor_std");
    if (!m.contains("outlier") || !m["outlier"].is_boolean()) bad(shown, at + ".outlier", "missing or not true/false");
    motor.outlier = m["outlier"].get<bool>();
    motor.reason = m.value("reason", "");
    if (m.contains("t") && !m["t"].is_null()) motor.t = number(m["t"], shown, at + ".t");
    motor.cycles = static_cast<std::size_t>(number(m.value("cycles", nlohmann::json()), shown, at + ".cycles"));
    if (!m.contains("metrics") || !m["metrics"].is_object()) bad(shown, at + ".metrics", "missing or not an object");
    motor.rmse_stator_k = number(m["metrics"].value("rmse_stator_k", nlohmann::json()), shown, at + ".metrics.rmse_stator_k");
    if (m["metrics"].contains("rmse_rotor_k"))
      motor.rmse_rotor_k = number(m["metrics"]["rmse_rotor_k"], shown, at + ".metrics.rmse_rotor_k");
    if (!m.contains("parameters") || !m["parameters"].is_array()) bad(shown, at + ".parameters", "missing or not a list");
    for (std::size_t k = 0; k < m["parameters"].size(); ++k) {
      const auto& p = m["parameters"][k];
      const std::string field = at + ".parameters[" + std::to_string(k) + "]";
      if (!p.is_object() || !p.contains("name") || !p["name"].is_string()) bad(shown, field + ".name", "missing");
      const int i = param_index(p["name"].get<std::string>());
      if (i < 0) bad(shown, field + ".name", "unknown parameter '" + p["name"].get<std::string>() + "'");
      motor.parameters[static_cast<std::size_t>(i)] = number(p.value("value", nlohmann::json()), shown, field + ".value");
    }
    out.motors.push_back(motor);
  }
  return out;
}

CalibrationResult motor_calibration(const FleetFile& fleet, const std::string& id) {
  for (const FleetFileMotor& m : fleet.motors) {
    if (m.id != id) continue;
    CalibrationResult c = fleet.pooled;
    for (ParameterResult& p : c.parameters) {
      const int i = param_index(p.name);
      if (i >= 0) p.value = m.parameters[static_cast<std::size_t>(i)];
    }
    c.details["fleet_motor"] = {{"id", m.id}, {"cooling_factor", m.cooling_factor}, {"outlier", m.outlier}};
    return c;
  }
  std::string known;
  for (const FleetFileMotor& m : fleet.motors) known += (known.empty() ? "" : ", ") + m.id;
  throw std::invalid_argument("--motor-id: no motor '" + id + "' in the fleet (its motors: " + known + ")");
}

}  // namespace lptn
