#include "trainer/diagnose/in_words.hpp"

#include <cstdio>
#include <string_view>

namespace lptn::diagnose {
namespace {

double value_of(int effect, int k, const ParamVector<double>& values) {
  return values[static_cast<std::size_t>(kNumPaperParams + EffectLibrary::kParamOffsets[effect] + k)];
}

std::string watts(double w) {
  char buf[32];
  if (w >= 1000) std::snprintf(buf, sizeof buf, "%.2f kW", w / 1000);
  else std::snprintf(buf, sizeof buf, "%.0f W", w);
  return buf;
}

bool starts_with(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

}  // namespace

std::string node_id(int effect) {
  const int node = EffectLibrary::kNodes[static_cast<std::size_t>(effect)];
  return node < 0 ? std::string() : std::string(terms::kNodeIds[node]);
}

std::string in_words(int effect, const ParamVector<double>& values) {
  const auto e = static_cast<std::size_t>(effect);
  const std::string_view name = EffectLibrary::kNames[e];
  const std::string summary(EffectLibrary::kSummaries[e]);
  char buf[256];
  if (EffectLibrary::kKinds[e] == EffectKind::term) {
    if (starts_with(name, "heat_") && name.find("_above_") != std::string_view::npos) {
      // A step: its second parameter is the threshold, a share of the rated frequency or current.
      std::snprintf(buf, sizeof buf, "%s, at %.0f %% of the rated %s, %s above it", summary.c_str(),
                    100 * value_of(effect, 1, values), name.ends_with("_f") ? "frequency" : "current",
                    watts(value_of(effect, 0, values)).c_str());
    } else if (starts_with(name, "heat_")) {
      std::snprintf(buf, sizeof buf, "%s with k = %.2f, %s at the rated point", summary.c_str(),
                    value_of(effect, 1, values), watts(value_of(effect, 0, values)).c_str());
    } else if (starts_with(name, "cooling_")) {
      std::snprintf(buf, sizeof buf, "%s with k = %.2f, %+.0f %% at base speed", summary.c_str(),
                    value_of(effect, 1, values), 100 * value_of(effect, 0, values));
    } else if (starts_with(name, "mass_")) {
      const double lambda = value_of(effect, 0, values), capacity_kj = value_of(effect, 1, values),
                   air = value_of(effect, 2, values);
      std::snprintf(buf, sizeof buf, "%s of %.0f kJ/K, %.0f W/K to it and %.0f W/K to the air (time constant %.0f min)",
                    summary.c_str(), capacity_kj, lambda, air, capacity_kj * 1000 / (lambda + air) / 60);
    } else if (starts_with(name, "airflow_")) {
      std::snprintf(buf, sizeof buf, "%s: %.2f instead of 0.8", summary.c_str(), 0.8 + value_of(effect, 0, values));
    } else {
      std::snprintf(buf, sizeof buf, "%s of %.1f W/K", summary.c_str(), value_of(effect, 0, values));
    }
    return buf;
  }
  std::string out = summary + ":";
  for (int k = 0; k < EffectLibrary::kParamCounts[e]; ++k) {
    const ParamSpec& s = param_spec(kNumPaperParams + EffectLibrary::kParamOffsets[e] + k);
    std::snprintf(buf, sizeof buf, " %s %.4g %s", std::string(s.name).c_str(), value_of(effect, k, values),
                  std::string(s.unit).c_str());
    out += buf;
  }
  return out;
}

}  // namespace lptn::diagnose
