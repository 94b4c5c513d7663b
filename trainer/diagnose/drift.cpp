#include "trainer/diagnose/drift.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <optional>
#include <thread>

#include "hostio/worker_threads.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/model/cooling_factor.hpp"
#include "trainer/diagnose/internal/cycle_span.hpp"
#include "trainer/diagnose/internal/permutation.hpp"

namespace lptn::diagnose {
namespace {

constexpr double kMinLogFactor = -1.0, kMaxLogFactor = 1.0;  // c in [0.37, 2.7]
// log c to within this: a fiftieth of kFactorResolution.
constexpr double kLogFactorTolerance = 1e-4;
constexpr int kMaxEvaluations = 40;  // Brent's worst case on [-1, 1] to 1e-4 is about 30
// A cycle's factor is not more precise than this (log units) whatever its fit says: it keeps the
// t statistics finite when cycles agree to the last digit.
constexpr double kFactorResolution = 0.005;

double squared_error(const calibrate::CycleMetrics& m) {
  double sse = 0;
  for (const ErrorMetrics* e : {&m.stator, &m.rotor})
    if (e->samples) sse += e->rmse_k * e->rmse_k * static_cast<double>(e->samples);
  return sse;
}

double squared_error(const Model<double>& model, const ParamVector<double>& p, const data::Cycle& cycle,
                     const PreparedCycle& prepared) {
  return squared_error(calibrate::evaluate_cycle(model, p, cycle, &prepared));
}

struct Evaluated {  // a log factor and the error there
  double x, f;
};

// The step from x to the vertex of the parabola through x, w and v, as the fraction step / q with
// q >= 0: Brent's tests compare the step with q times a length, so it is not divided out here.
struct ParabolicStep {
  double step, q;
};
ParabolicStep parabolic_step(Evaluated x, Evaluated w, Evaluated v) {
  const double r = (x.x - w.x) * (x.f - v.f), q = (x.x - v.x) * (x.f - w.f);
  const double step = (x.x - v.x) * q - (x.x - w.x) * r, twice = 2 * (q - r);
  return {twice > 0 ? -step : step, std::abs(twice)};
}

// The log factor in [kMinLogFactor, kMaxLogFactor] that minimizes f: Brent's minimizer
// (golden-section steps, parabolic ones where the error is smooth, which it is: 10.6 cycle
// simulations on average on a clean 48 h dump, where the golden section alone took 24).
template <class F>
double brent_minimum(const F& f) {
  constexpr double kGolden = 0.3819660112501051;  // 2 - phi
  double a = kMinLogFactor, b = kMaxLogFactor;
  double x = a + kGolden * (b - a), w = x, v = x;
  double fx = f(x), fw = fx, fv = fx;
  double d = 0, e = 0;  // the last step and the one before it
  for (int evaluations = 1; evaluations < kMaxEvaluations; ++evaluations) {
    const double m = 0.5 * (a + b), tol = 0.5 * kLogFactorTolerance;
    if (std::abs(x - m) <= 2 * tol - 0.5 * (b - a)) break;
    bool parabolic = false;
    if (std::abs(e) > tol) {
      // The parabola through x, w and v; its minimum if it falls inside and the step shrinks.
      const auto [step, q] = parabolic_step({x, fx}, {w, fw}, {v, fv});
      if (std::abs(step) < std::abs(0.5 * q * e) && step > q * (a - x) && step < q * (b - x)) {
        e = d;
        d = step / q;
        const double u = x + d;
        if (u - a < 2 * tol || b - u < 2 * tol) d = x < m ? tol : -tol;
        parabolic = true;
      }
    }
    if (!parabolic) {
      e = (x < m ? b : a) - x;
      d = kGolden * e;
    }
    const double u = std::abs(d) >= tol ? x + d : x + (d > 0 ? tol : -tol);
    const double fu = f(u);
    if (fu <= fx) {
      (u < x ? b : a) = x;
      v = w, fv = fw, w = x, fw = fx, x = u, fx = fu;
    } else {
      (u < x ? a : b) = u;
      if (fu <= fw || w == x) {
        v = w, fv = fw, w = u, fw = fu;
      } else if (fu <= fv || v == x || v == w) {
        v = u, fv = fu;
      }
    }
  }
  return x;
}

// Successive parabolic interpolation from the baseline (log c = 0, its error f0 known: both groups
// share it) and a step to either side: where the cycle's factor is near 1, as on most cycles of a
// dump that does not drift, the error is close to a parabola in log c over that span, and the
// vertex settles after one or two more simulations (3.7 on average on a clean 48 h dump, where
// Brent's bracket of the whole range took 10.6; the two agree to 6e-5 in log c). It returns the
// vertex once a parabola through an evaluated vertex moves it by less than the tolerance.
// Where the three do not bracket a minimum (a cycle whose factor lies beyond the step: 39 of the
// clean 200 h dump's 320, shunting cycles most, within 0.02..0.07 of it), the bracket is first
// stretched downhill by golden-ratio steps, as Numerical Recipes' mnbrak does: one or two
// simulations where Brent's minimizer over the whole range took 12.5. None where the baseline is
// above both steps (not convex there), where the stretch leaves the range, where a parabola is
// not convex or its vertex leaves the bracket, or where it does not settle: Brent's minimizer then
// takes the whole range.
constexpr double kBaselineStep = 0.02;  // log units: four times kFactorResolution
constexpr int kMaxParabolicSteps = 8;
constexpr double kGoldenRatio = 1.618033988749895;

// Three points with the lowest in the middle (by position): the minimum's bracket, or none.
template <class F>
std::optional<std::array<Evaluated, 3>> bracket_from_baseline(const F& f, double f0) {
  Evaluated low{-kBaselineStep, f(-kBaselineStep)}, mid{0.0, f0}, high{kBaselineStep, f(kBaselineStep)};
  if (mid.f < low.f && mid.f < high.f) return std::array<Evaluated, 3>{low, mid, high};
  if (!(low.f < mid.f) && !(high.f < mid.f)) return std::nullopt;  // flat at the baseline, or NaN
  if (low.f < mid.f && high.f < mid.f) return std::nullopt;         // above both sides: not convex
  // Downhill from `from` through `to`, one golden-ratio step further each time.
  Evaluated from = mid, to = low.f < mid.f ? low : high;
  while (true) {
    const double x = to.x + kGoldenRatio * (to.x - from.x);
    if (!(x > kMinLogFactor && x < kMaxLogFactor)) return std::nullopt;
    const Evaluated next{x, f(x)};
    if (next.f > to.f) return x < from.x ? std::array<Evaluated, 3>{next, to, from} : std::array<Evaluated, 3>{from, to, next};
    from = to;
    to = next;
  }
}

template <class F>
std::optional<double> parabolic_from_baseline(const F& f, double f0) {
  const std::optional<std::array<Evaluated, 3>> bracket = bracket_from_baseline(f, f0);
  if (!bracket) return std::nullopt;
  std::array<Evaluated, 3> p = *bracket;
  double lo = p[0].x, hi = p[2].x;  // the minimum's bracket
  const double tol = 0.5 * kLogFactorTolerance;
  for (int step = 0; step < kMaxParabolicSteps; ++step) {
    std::sort(p.begin(), p.end(), [](const Evaluated& a, const Evaluated& b) { return a.f < b.f; });
    const Evaluated &x = p[0], &w = p[1], &v = p[2];
    // The parabola through the three: its curvature (the second divided difference) and vertex.
    const double curvature = ((v.f - x.f) / (v.x - x.x) - (w.f - x.f) / (w.x - x.x)) / (v.x - w.x);
    const auto [step_to_vertex, q] = parabolic_step(x, w, v);
    const double u = x.x + step_to_vertex / q;
    if (!(curvature > 0) || !(u > lo && u < hi)) return std::nullopt;
    if (step > 0 && std::abs(u - x.x) < tol) return u;
    const double fu = f(u);
    if (fu < x.f) {
      (u < x.x ? hi : lo) = x.x;
    } else {
      (u < x.x ? lo : hi) = u;
    }
    p[2] = {u, fu};  // the worst of the three gives way
  }
  return std::nullopt;
}

// The factor of the group that fits `cycle` best, the other parameters at `p`; `f0` its error at
// factor 1 (both groups share it).
double best_factor(const Model<double>& model, const ParamVector<double>& p, DriftGroup g, const data::Cycle& cycle,
                   const PreparedCycle& prepared, double f0) {
  auto f = [&](double y) { return squared_error(model, scaled_group(p, g, std::exp(y)), cycle, prepared); };
  if (const std::optional<double> y = parabolic_from_baseline(f, f0)) return std::exp(*y);
  return std::exp(brent_minimum(f));
}

struct Statistic {
  double t = 0;
  std::size_t split = 0;  // step: first changed cycle
};

double mean(const std::vector<double>& y, std::size_t from, std::size_t to) {
  return std::accumulate(y.begin() + static_cast<std::ptrdiff_t>(from), y.begin() + static_cast<std::ptrdiff_t>(to), 0.0) /
         static_cast<double>(to - from);
}

Statistic step_statistic(const std::vector<double>& y) {
  const std::size_t n = y.size();
  Statistic best;
  for (std::size_t k = 2; k + 2 <= n; ++k) {
    const double m1 = mean(y, 0, k), m2 = mean(y, k, n);
    double ss = 0;
    for (std::size_t i = 0; i < n; ++i) ss += (y[i] - (i < k ? m1 : m2)) * (y[i] - (i < k ? m1 : m2));
    const double s2 = std::max(ss / static_cast<double>(n - 2), kFactorResolution * kFactorResolution);
    const double t = std::abs(m2 - m1) / std::sqrt(s2 * (1.0 / static_cast<double>(k) + 1.0 / static_cast<double>(n - k)));
    if (t > best.t) best = {t, k};
  }
  return best;
}

// The least-squares line through y over the cycle index: its slope and that slope's t statistic.
struct Trend {
  double slope = 0, t = 0;
};

Trend trend_of(const std::vector<double>& y) {
  const std::size_t n = y.size();
  const double xm = 0.5 * static_cast<double>(n - 1), ym = mean(y, 0, n);
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sxx += (static_cast<double>(i) - xm) * (static_cast<double>(i) - xm);
    sxy += (static_cast<double>(i) - xm) * (y[i] - ym);
  }
  const double slope = sxy / sxx;
  double ss = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = y[i] - ym - slope * (static_cast<double>(i) - xm);
    ss += r * r;
  }
  const double s2 = std::max(ss / static_cast<double>(n - 2), kFactorResolution * kFactorResolution);
  return {slope, std::abs(slope) / std::sqrt(s2 / sxx)};
}

double trend_statistic(const std::vector<double>& y) { return trend_of(y).t; }

}  // namespace

const char* to_string(DriftGroup g) { return g == DriftGroup::cooling ? "cooling" : "losses"; }

ParamVector<double> scaled_group(const ParamVector<double>& p, DriftGroup g, double c) {
  if (g == DriftGroup::cooling) return with_cooling_factor(p, c);
  ParamVector<double> out = p;
  for (int i : {kKStemp, kKRtemp}) out[i] *= c;
  return out;
}

namespace {
// The drift of one group, from every cycle's factor of it (in the dump's order).
Drift drift_of(DriftGroup group, const data::Dataset& dataset, const std::vector<double>& factors, int threads) {
  Drift d;
  d.group = group;
  const std::size_t n = dataset.cycles.size();
  d.factors.resize(n);
  for (std::size_t i = 0; i < n; ++i) d.factors[i] = {dataset.cycles[i].name, factors[i]};
  if (n < 4) return d;
  std::vector<double> y(n);
  for (std::size_t i = 0; i < n; ++i) y[i] = std::log(d.factors[i].factor);
  const Statistic step = step_statistic(y);
  const Trend trend = trend_of(y);
  const double p_step =
      internal::p_value(y, step.t, [](const std::vector<double>& v) { return step_statistic(v).t; }, threads);
  const double p_trend = internal::p_value(y, trend.t, trend_statistic, threads);

  if (p_step <= p_trend) {
    d.shape = "step";
    d.p_value = p_step;
    d.change = std::exp(mean(y, step.split, n) - mean(y, 0, step.split)) - 1;
    for (std::size_t i = step.split; i < n; ++i) d.cycles.push_back(d.factors[i].cycle);
  } else {
    d.shape = "trend";
    d.p_value = p_trend;
    d.change = std::exp(trend.slope * static_cast<double>(n - 1)) - 1;  // first to last cycle, along the fit
    for (std::size_t i = n / 2; i < n; ++i) d.cycles.push_back(d.factors[i].cycle);
  }
  d.found = d.p_value <= kDriftLevel && std::abs(d.change) >= kMinDriftChange;
  if (!d.found) {
    d.cycles.clear();
    return d;
  }
  char text[512];
  const bool cooling = group == DriftGroup::cooling;
  // A smaller cooling factor is weaker cooling; a larger loss factor is more heat.
  const char* direction = cooling ? (d.change < 0 ? "weaker" : "stronger") : (d.change > 0 ? "higher" : "lower");
  if (d.shape == "step")
    std::snprintf(text, sizeof text, "the %s of cycles %s is %.0f %% %s than the earlier cycles' (p = %.3f over %d orderings)",
                  cooling ? "cooling" : "copper loss", internal::cycle_span(d.cycles).c_str(), 100 * std::abs(d.change), direction,
                  d.p_value, internal::kOrderings);
  else
    std::snprintf(text, sizeof text,
                  "the %s grows %.0f %% %s from the first cycle to the last, most in cycles %s (p = %.3f over %d "
                  "orderings)",
                  cooling ? "cooling" : "copper loss", 100 * std::abs(d.change), direction, internal::cycle_span(d.cycles).c_str(),
                  d.p_value, internal::kOrderings);
  d.finding = text;
  d.inspect = cooling ? "the cooling air path of these cycles' motor: air filters, the blower and its supply, the "
                        "airflow signal's calibration; then calibrate on the cycles before the change"
                      : "the current and frequency signals of these cycles (scaling, a replaced sensor), the "
                        "converter's settings, the winding's insulation and connections";
  return d;
}

}  // namespace

Drift find_drift(const Model<double>& model, const ParamVector<double>& params, const data::Dataset& dataset,
                 int threads, const std::vector<const calibrate::CycleMetrics*>& at_params) {
  // Both groups' factors in one pass over the cycles: each cycle's losses prepared once, its
  // error at factor 1 simulated once (or read from `at_params`). The losses' factors are computed
  // even where the cooling's drift will be the finding, and then go unused (about four
  // simulations a cycle).
  const std::size_t n = dataset.cycles.size();
  std::vector<double> cooling(n), losses(n);
  hostio::parallel_for(n, threads, [&](std::size_t i) {
    const data::Cycle& cycle = dataset.cycles[i];
    const PreparedCycle prepared = prepare_cycle(model, cycle);
    const double f0 = i < at_params.size() && at_params[i] ? squared_error(*at_params[i]) : squared_error(model, params, cycle, prepared);
    cooling[i] = best_factor(model, params, DriftGroup::cooling, cycle, prepared, f0);
    losses[i] = best_factor(model, params, DriftGroup::losses, cycle, prepared, f0);
  });
  Drift by_cooling = drift_of(DriftGroup::cooling, dataset, cooling, threads);
  if (by_cooling.found) return by_cooling;
  Drift by_losses = drift_of(DriftGroup::losses, dataset, losses, threads);
  return by_losses.found ? by_losses : by_cooling;
}

nlohmann::json to_json(const Drift& d) {
  nlohmann::json factors = nlohmann::json::array();
  for (const CycleFactor& f : d.factors) factors.push_back({{"cycle", f.cycle}, {"factor", f.factor}});
  return {{"group", to_string(d.group)}, {"found", d.found},     {"shape", d.shape},
          {"p_value", d.p_value},        {"change", d.change},   {"cycles", d.cycles},
          {"finding", d.finding},        {"inspect", d.inspect}, {"factors", factors}};
}

}  // namespace lptn::diagnose
