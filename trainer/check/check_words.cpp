// lptn check's verdict as JSON and as text.
#include <cmath>
#include <cstdio>

#include "trainer/check/check.hpp"

namespace lptn::check {
namespace {

nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

std::string fixed(double v, const char* format) {
  if (!std::isfinite(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace

nlohmann::json to_json(const Check& c) {
  // diagnose's verdict per sensor, over every cycle given: no train or test side here.
  nlohmann::json adequacy = diagnose::to_json(c.adequacy);
  for (auto& [name, s] : adequacy["sensors"].items()) {
    s.erase("train_rmse_k");
    s.erase("test_rmse_k");
  }
  nlohmann::json cycles = nlohmann::json::array();
  for (const CycleCheck& cc : c.cycles) {
    nlohmann::json j = {{"name", cc.name},
                        {"holds", cc.holds},
                        {"seen", cc.provenance.seen},
                        {"role", cc.provenance.seen && !cc.provenance.role.empty() ? nlohmann::json(cc.provenance.role)
                                                                                   : nlohmann::json(nullptr)}};
    for (int s = 0; s < 2; ++s) {
      const std::string k = kSensorNames[s];
      const SensorCheck& sc = cc.sensors[s];
      j[k + "_rmse_k"] = sc.measured ? number(sc.rmse_k) : nullptr;
      j[k + "_over_noise"] = sc.measured ? number(sc.over_noise) : nullptr;
      j[k + "_over_calibration"] = sc.measured ? number(sc.over_calibration) : nullptr;
      j[k + "_beyond"] = sc.beyond;
    }
    j["cooling_factor"] = number(cc.cooling_factor);
    j["cooling_factor_std_log"] = number(cc.cooling_log_std_error);
    j["cooling_changed"] = cc.cooling_changed;
    if (!cc.provenance.seen) j["never_seen"] = cc.provenance.why;
    cycles.push_back(j);
  }
  return {{"holds", c.holds},
          {"reasons", c.reasons},
          {"adequate", adequacy["adequate"]},
          {"adequate_within", adequacy["adequate_within"]},
          {"sensors", adequacy["sensors"]},
          {"thresholds",
           {{"error_over_noise", diagnose::kAdequateRatio},
            {"error_over_calibration", kOverCalibrationError},
            {"cooling_change", kMinCoolingChange},
            {"cooling_z", kCoolingZ}}},
          {"calibration_error_k", {{"stator", number(c.calibration_error_k[0])}, {"rotor", number(c.calibration_error_k[1])}}},
          {"cooling_factor", number(c.cooling_factor)},
          {"cooling_factor_std_log", number(c.cooling_log_std_error)},
          {"data",
           {{"never_seen", c.provenance.unseen_names()},
            {"constants", c.provenance.constants},
            {"summary", c.provenance.summary()}}},
          {"cycles", cycles}};
}

std::string describe(const Check& c) {
  std::string out;
  char line[512];
  std::snprintf(line, sizeof line, "%-26s %-9s %9s %7s %7s %9s %7s %7s %14s  %s\n", "cycle", "data", "stator K", "/noise",
                "/cal.", "rotor K", "/noise", "/cal.", "cooling", "holds");
  out += line;
  for (const CycleCheck& cc : c.cycles) {
    const std::string data = cc.provenance.seen ? (cc.provenance.role.empty() ? "seen" : cc.provenance.role) : "new";
    std::string cooling = fixed(cc.cooling_factor, "%.3f");
    if (std::isfinite(cc.cooling_log_std_error)) cooling += " ±" + fixed(cc.cooling_factor * cc.cooling_log_std_error, "%.3f");
    const SensorCheck& st = cc.sensors[0];
    const SensorCheck& ro = cc.sensors[1];
    std::snprintf(line, sizeof line, "%-26s %-9s %9s %7s %7s %9s %7s %7s %14s  %s\n", cc.name.c_str(), data.c_str(),
                  fixed(st.rmse_k, "%.3f").c_str(), fixed(st.over_noise, "%.1fx").c_str(),
                  fixed(st.over_calibration, "%.1fx").c_str(), fixed(ro.rmse_k, "%.3f").c_str(),
                  fixed(ro.over_noise, "%.1fx").c_str(), fixed(ro.over_calibration, "%.1fx").c_str(), cooling.c_str(),
                  cc.holds ? "yes" : "NO");
    out += line;
  }
  std::snprintf(line, sizeof line,
                "bounds: a sensor's RMSE within max(%.1fx its noise, %.0fx the calibration's own test error); the cooling "
                "factor within %.0f %% of 1 or within %.0f standard errors\n",
                diagnose::kAdequateRatio, kOverCalibrationError, kMinCoolingChange * 100, kCoolingZ);
  out += line;
  for (int s = 0; s < 2; ++s)
    if (std::isfinite(c.calibration_error_k[s])) {
      std::snprintf(line, sizeof line, "the calibration's own %s test error: %.3f K\n", kSensorNames[s], c.calibration_error_k[s]);
      out += line;
    }
  out += "the model against its sensors' noise on this data (as lptn diagnose judges it):\n";
  for (const diagnose::SensorAdequacy& a : c.adequacy.sensors) {
    // Every cycle given is one side here: diagnose's describe() would call it "train".
    std::snprintf(line, sizeof line, "  %s: RMSE %.3f K = %.1fx its noise of %.3f K (estimated from its readings): %s",
                  a.sensor.c_str(), a.train_rmse_k, a.train_rmse_k / a.noise_k, a.noise_k,
                  a.adequate ? "adequate" : "something is missing");
    out += line;
    if (!a.adequate && !a.cycles.empty()) out += " (worst: " + a.cycles.front() + ")";
    out += "\n";
  }
  if (!c.provenance.all_seen()) out += "data this calibration never saw: " + c.provenance.summary() + "\n";
  if (c.holds) {
    std::snprintf(line, sizeof line, "the calibration holds on this data (cooling factor %.3f, 1 = as calibrated)\n",
                  c.cooling_factor);
    out += line;
  } else {
    out += "the calibration does NOT hold on this data:\n";
    for (const std::string& r : c.reasons) out += "  " + r + "\n";
  }
  return out;
}

}  // namespace lptn::check
