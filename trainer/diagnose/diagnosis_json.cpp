// The diagnosis as JSON (lptn diagnose --json).
#include <cmath>

#include "trainer/diagnose/diagnose.hpp"

namespace lptn::diagnose {
namespace {

// NaN (no test cycles, no standard error) as null.
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json to_json(const Candidate& c, const Diagnosis& d) {
  nlohmann::json params = nlohmann::json::object();
  for (int i = 0; i < kNumParams; ++i)
    if (effect_of_param(i) == c.effect)
      params[std::string(param_spec(i).name)] = {{"value", c.refit.values[i]}, {"std_error", number(c.refit.std_error[i])},
                                                 {"unit", std::string(param_spec(i).unit)}};
  return {{"effect", c.name},
          {"statistic", c.statistic},
          {"threshold", c.threshold},
          {"df", c.df},
          {"score", c.score},
          {"predicted_rmse_k", c.predicted_rmse_k},
          {"refit_rmse_k", c.refit_rmse_k},
          {"train_stator_rmse_k", number(c.train_stator_rmse_k)},
          {"test_stator_rmse_k", number(c.test_stator_rmse_k)},
          {"significant", c.verdict == Verdict::significant},
          {"kind", "library"},
          {"recommended", d.best() == &c},
          {"test_rmse_k_before", number(d.test_rmse_k)},
          {"test_rmse_k_after", number(c.test_rmse_k_after)},
          {"verdict", to_string(c.verdict)},
          {"reason", c.reason},
          {"needs", c.needs},
          {"parameters", params},
          {"refit_iterations", c.refit.iterations},
          {"refit_converged", c.refit.converged},
          {"refit_seconds", c.refit.seconds}};
}

}  // namespace

nlohmann::json to_json(const Diagnosis& d) {
  nlohmann::json candidates = nlohmann::json::array();
  for (const Candidate& c : d.candidates) candidates.push_back(to_json(c, d));
  nlohmann::json j = to_json(d.adequacy);  // "adequate" and "sensors" first: the verdict on the model itself
  j["rmse_k"] = d.rmse_k;
  j["candidates"] = candidates;
  return j;
}

}  // namespace lptn::diagnose
