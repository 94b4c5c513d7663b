// What every diagnosis the suites run must hold (issue 27, parts 3 and 4), checked on each of them
// beside the suite's own assertions, so that it costs no diagnosis of its own:
//   - a judged candidate's refit ends at or below the baseline it started from (one that cannot is
//     listed as a failed refit, not judged);
//   - a recommended candidate's size is pinned: its standard error at most half its value.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "trainer/diagnose/diagnose.hpp"

namespace lptn::diagnose {

// The candidate's first parameter: its size, whose neutral value (0) is "absent".
inline int size_parameter(const Candidate& c) {
  return kNumPaperParams + EffectLibrary::kParamOffsets[static_cast<std::size_t>(c.effect)];
}

inline void expect_sound_candidates(const Diagnosis& d, const std::string& label) {
  int judged = 0, above = 0;
  for (const Candidate& c : d.candidates) {
    if (c.verdict == Verdict::refit_failed) {
      EXPECT_FALSE(c.reason.empty()) << label << ": " << c.name << " failed without saying why";
      continue;
    }
    ++judged;
    above += c.refit_rmse_k > d.rmse_k;
    EXPECT_LE(c.refit_rmse_k, d.rmse_k) << label << ": " << c.name << " is judged ("
                                        << to_string(c.verdict) << ") on a refit above its baseline";
  }
  std::printf("%s: %d of %d judged candidates end above the baseline (%.3f K)\n", label.c_str(), above, judged,
              d.rmse_k);
  if (const Candidate* best = d.best()) {
    const int i = size_parameter(*best);
    const double v = best->refit.values[i], se = best->refit.std_error[i];
    std::printf("%s: recommended %s, %s = %.4g +- %.2g (%.0f %% of its value)\n", label.c_str(), best->name.c_str(),
                std::string(param_spec(i).name).c_str(), v, se, 100 * se / std::abs(v));
    EXPECT_TRUE(std::isfinite(se) && se <= 0.5 * std::abs(v))
        << label << ": " << best->name << " recommended with " << param_spec(i).name << " = " << v << " +- " << se;
    EXPECT_LT(best->test_rmse_k_after, d.test_rmse_k) << label << ": recommended without a fall of the held-out error";
  }
}

// The same on `lptn diagnose --json`'s output (one diagnosis, or one round of --auto).
inline void expect_sound_candidates(const nlohmann::json& d, const std::string& label) {
  const double baseline = d.at("rmse_k").get<double>();
  for (const auto& c : d.at("candidates")) {
    if (c.at("kind") == "drift") continue;
    if (c.at("verdict") == "refit failed") {
      EXPECT_FALSE(c.at("reason").get<std::string>().empty()) << label << ": " << c.dump();
      continue;
    }
    EXPECT_LE(c.at("refit_rmse_k").get<double>(), baseline) << label << ": " << c.at("effect");
    if (!c.at("recommended").get<bool>()) continue;
    for (const auto& [name, p] : c.at("parameters").items())
      if (name == param_spec(kNumPaperParams + EffectLibrary::kParamOffsets[static_cast<std::size_t>(
                                                   effect_index(c.at("effect").get<std::string>()))]).name) {
        ASSERT_FALSE(p.at("std_error").is_null()) << label << ": " << c.dump();
        EXPECT_LE(p.at("std_error").get<double>(), 0.5 * std::abs(p.at("value").get<double>())) << label << ": " << name;
      }
  }
}

}  // namespace lptn::diagnose
