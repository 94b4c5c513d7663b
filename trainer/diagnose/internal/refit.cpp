#include "trainer/diagnose/internal/refit.hpp"

#include <cmath>
#include <cstdio>

namespace lptn::diagnose::internal {
namespace {

// "P is +0.97 correlated with Q" for the first flagged pair with parameter `i`, or empty.
std::string confounded(const LmReport& fit, int i) {
  const std::string name(param_spec(i).name);
  for (const CorrelatedPair& c : fit.correlated) {
    if (c.a != name && c.b != name) continue;
    char buf[256];
    std::snprintf(buf, sizeof buf, "%s is %+.3f correlated with %s", name.c_str(), c.correlation,
                  (c.a == name ? c.b : c.a).c_str());
    return buf;
  }
  return {};
}

// "P = v +- se: its standard error exceeds its value", or empty.
std::string imprecise(const LmReport& fit, int i) {
  const std::string name(param_spec(i).name);
  const double v = fit.values[i], se = fit.std_error[i];
  if (std::isnan(se)) return name + " has no standard error (the data's information about it is singular)";
  if (se <= std::abs(v)) return {};
  char buf[256];
  std::snprintf(buf, sizeof buf, "%s = %.3g +- %.3g %s: its standard error exceeds its value", name.c_str(), v, se,
                std::string(param_spec(i).unit).c_str());
  return buf;
}

}  // namespace

Refit refit_with(const MotorFile& with_effect, int effect, const ParamVector<double>& start, const data::Dataset& dataset,
                 const std::vector<std::size_t>& train, const LmSettings& settings, const LmProgress& progress) {
  Refit out;
  out.fit = fit_lm(with_effect, start, dataset, train, settings, progress);
  for (int i : FreeParameters::from_motor(with_effect).index) {
    if (effect_of_param(i) != effect) continue;
    if (out.confounded.empty()) out.confounded = confounded(out.fit, i);
    if (out.imprecise.empty()) out.imprecise = imprecise(out.fit, i);
  }
  return out;
}

}  // namespace lptn::diagnose::internal
