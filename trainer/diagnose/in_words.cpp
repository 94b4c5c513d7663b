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

std::string formatted(double v, WordStyle style) {
  char buf[48];
  switch (style) {
    case WordStyle::none: return {};
    case WordStyle::fixed2: std::snprintf(buf, sizeof buf, "%.2f", v); break;
    case WordStyle::watts: return watts(v);
    case WordStyle::percent: std::snprintf(buf, sizeof buf, "%.0f %%", 100 * v); break;
    case WordStyle::signed_percent: std::snprintf(buf, sizeof buf, "%+.0f %%", 100 * v); break;
    case WordStyle::whole: std::snprintf(buf, sizeof buf, "%.0f", v); break;
    case WordStyle::one_decimal: std::snprintf(buf, sizeof buf, "%.1f", v); break;
    case WordStyle::plus_0_8: std::snprintf(buf, sizeof buf, "%.2f", 0.8 + v); break;
  }
  return buf;
}

}  // namespace

std::string node_id(int effect) {
  const int node = EffectLibrary::kNodes[static_cast<std::size_t>(effect)];
  return node < 0 ? std::string() : std::string(terms::kNodeIds[node]);
}

// The effect's own words (its kWords, common/lptn/effects/effect.hpp), or its summary and each
// parameter with its unit.
std::string in_words(int effect, const ParamVector<double>& values) {
  const auto e = static_cast<std::size_t>(effect);
  std::string out(EffectLibrary::kSummaries[e]);
  const auto words = EffectLibrary::kWords[e];
  if (!words.empty()) {
    const double* p = values.data() + kNumPaperParams + EffectLibrary::kParamOffsets[e];
    for (const WordPart& w : words) {
      out += w.text;
      if (w.derived) out += formatted(EffectLibrary::kDerived[e](p), w.style);
      else if (w.param >= 0) out += formatted(value_of(effect, w.param, values), w.style);
    }
    return out;
  }
  out += ":";
  char buf[256];
  for (int k = 0; k < EffectLibrary::kParamCounts[e]; ++k) {
    const ParamSpec& s = param_spec(kNumPaperParams + EffectLibrary::kParamOffsets[e] + k);
    std::snprintf(buf, sizeof buf, " %s %.4g %s", std::string(s.name).c_str(), value_of(effect, k, values),
                  std::string(s.unit).c_str());
    out += buf;
  }
  return out;
}

}  // namespace lptn::diagnose
