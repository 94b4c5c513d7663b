#include "trainer/fleet/fleet_file.hpp"

#include <stdexcept>

#include "hostio/atomic_file.hpp"
#include "hostio/bad_input.hpp"

namespace lptn::fleet {

nlohmann::ordered_json fleet_json(const calibrate::CalibrationResult& pooled, const FleetFit& fit, const FleetSettings& settings) {
  nlohmann::ordered_json j;
  j["format_version"] = kFleetFormatVersion;
  j["pooled"] = nlohmann::ordered_json::parse(calibrate::to_json(pooled).dump());  // keeps calibration.json's key order
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
    o["metrics"] = calibrate::split_metrics_json(m.metrics);
    o["parameters"] = nlohmann::ordered_json::array();
    for (int i = 0; i < kNumParams; ++i)
      o["parameters"].push_back({{"name", std::string(param_spec(i).name)},
                                 {"unit", std::string(param_spec(i).unit)},
                                 {"value", m.parameters[static_cast<std::size_t>(i)]}});
    motors[m.id] = o;
  }
  return j;
}

void save_fleet(const std::filesystem::path& path, const calibrate::CalibrationResult& pooled, const FleetFit& fit,
                const FleetSettings& settings) {
  hostio::write_file_atomically(path, fleet_json(pooled, fit, settings).dump(2) + "\n");
}

FleetFile load_fleet_file(const std::filesystem::path& path) {
  const std::string shown = path.string();
  const nlohmann::json j = calibrate::read_lptn_json(path);
  if (j.is_object() && j.contains("parameters") && j.contains("motor") && !j.contains("pooled"))
    throw calibrate::CalibrationFileError(shown + ": a single motor's calibration (calibration.json), not a fleet calibration: give "
                                       "it as --calibration");
  const hostio::JsonField root(j, "", shown);
  if (!root.has("format_version")) throw calibrate::CalibrationFileError(shown + ": not a fleet calibration (no format_version)");
  const hostio::JsonField version = root["format_version"];
  if (version.integer() != kFleetFormatVersion)
    version.fail("version " + j["format_version"].dump() + ", this lptn reads " + std::to_string(kFleetFormatVersion));
  FleetFile out;
  out.pooled = calibrate::calibration_from_json(root["pooled"].json(), shown + " (pooled)");
  const hostio::JsonField fleet = root["fleet"];
  out.rounds = static_cast<int>(fleet["rounds"].count());
  const hostio::JsonField outlier_test = fleet["outlier_test"];
  out.family_alpha = outlier_test["family_alpha"].number();
  if (outlier_test.has("threshold_t")) out.threshold_t = outlier_test["threshold_t"].number_or_null();
  const hostio::JsonField motors = root["motors"];
  motors.expect_object();
  for (const auto& [id, m] : j["motors"].items()) {
    const hostio::JsonField motor_field = motors[id.c_str()];
    FleetFileMotor motor;
    motor.id = id;
    motor.parameters = out.pooled.values();
    motor.cooling_factor = motor_field["cooling_factor"].number();
    motor.cooling_factor_std = motor_field["cooling_factor_std"].number();
    motor.outlier = motor_field["outlier"].boolean();
    if (motor_field.has("reason")) motor.reason = motor_field["reason"].string();
    if (motor_field.has("t")) motor.t = motor_field["t"].number_or_null();
    motor.cycles = motor_field["cycles"].count();
    const hostio::JsonField metrics = motor_field["metrics"];
    motor.rmse_stator_k = metrics["rmse_stator_k"].number();
    if (metrics.has("rmse_rotor_k")) motor.rmse_rotor_k = metrics["rmse_rotor_k"].number_or_null();
    const hostio::JsonField parameters = motor_field["parameters"];
    for (std::size_t k = 0; k < parameters.size(); ++k) {
      const hostio::JsonField name = parameters.at(k)["name"];
      const int i = param_index(name.string());
      if (i < 0) name.fail("unknown parameter '" + name.string() + "'");
      motor.parameters[static_cast<std::size_t>(i)] = parameters.at(k)["value"].number();
    }
    out.motors.push_back(motor);
  }
  return out;
}

calibrate::CalibrationResult motor_calibration(const FleetFile& fleet, const std::string& id) {
  for (const FleetFileMotor& m : fleet.motors) {
    if (m.id != id) continue;
    calibrate::CalibrationResult c = fleet.pooled;
    for (calibrate::ParameterResult& p : c.parameters) {
      const int i = param_index(p.name);
      if (i >= 0) p.value = m.parameters[static_cast<std::size_t>(i)];
    }
    c.details["fleet_motor"] = {{"id", m.id}, {"cooling_factor", m.cooling_factor}, {"outlier", m.outlier}};
    return c;
  }
  std::string known;
  for (const FleetFileMotor& m : fleet.motors) known += (known.empty() ? "" : ", ") + m.id;
  throw hostio::BadInput("--motor-id: no motor '" + id + "' in the fleet (its motors: " + known + ")");
}

}  // namespace lptn::fleet
