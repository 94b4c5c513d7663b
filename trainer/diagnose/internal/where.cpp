#include "trainer/diagnose/internal/where.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace lptn::diagnose::internal {
namespace {

using data::Channel;

constexpr struct {
  const char* name;
  Channel channel;
} kInputs[kFollowInputs] = {{"speed", Channel::speed_rpm},         {"current", Channel::current_a},
                            {"torque", Channel::torque_nm},        {"frequency", Channel::frequency_hz},
                            {"airflow", Channel::airflow_m3s},     {"ambient", Channel::ambient_c}};

std::size_t one_hertz(const data::Cycle& cycle) {
  return std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(1.0 / cycle.dt_s)));
}

int tertile(double x, const std::array<double, 2>& edges) { return x < edges[0] ? 0 : x < edges[1] ? 1 : 2; }

// The value below which `share` of a histogram's mass lies.
double quantile(const std::vector<double>& hist, double lo, double hi, double share) {
  double total = 0;
  for (double h : hist) total += h;
  double seen = 0;
  for (std::size_t i = 0; i < hist.size(); ++i) {
    seen += hist[i];
    if (seen >= share * total) return lo + (hi - lo) * static_cast<double>(i + 1) / static_cast<double>(hist.size());
  }
  return hi;
}

std::string range(const char* word, const char* what, const std::array<double, 2>& r, const char* unit) {
  char s[128];
  std::snprintf(s, sizeof s, "%s %s (%.0f..%.0f %s)", word, what, r[0], r[1], unit);
  return s;
}

constexpr double kOneOverE = 1 / std::numbers::e;

// Pearson's correlation from sums (NaN with fewer than 10 pairs or no variance).
double correlation(double n, double sx, double sxx, double sxy, double sy, double syy) {
  if (n < 10) return NAN;
  const double vx = sxx - sx * sx / n, vy = syy - sy * sy / n;
  if (!(vx > 0) || !(vy > 0)) return NAN;
  return (sxy - sx * sy / n) / std::sqrt(vx * vy);
}

// The residual at 1 Hz (NaN between the readings of a sensor read more slowly) and the sensor's
// reading, the last at or before each second (for its rate of warming over a window).
void add_shape_sums(WhereSums& s, const data::Cycle& cycle, Channel sensor, const std::vector<float>& residual) {
  const std::size_t every = one_hertz(cycle);
  const std::size_t n = std::min(cycle.steps, residual.size()) / every;
  std::vector<double> r(n, NAN), y(n, NAN);
  double last_y = NAN;
  for (std::size_t i = 0, k = 0; i < n; ++i) {
    for (; k <= i * every; ++k)
      if (const double v = cycle.at(sensor, k); std::isfinite(v)) last_y = v;
    r[i] = residual[i * every];
    y[i] = last_y;
  }
  for (std::size_t l = 0; l < kShapeLagsS.size(); ++l) {
    const auto lag = static_cast<std::size_t>(std::lround(kShapeLagsS[l] / (static_cast<double>(every) * cycle.dt_s)));
    if (lag == 0) continue;
    for (std::size_t i = 0; i + lag < n; ++i) {
      const double a = r[i], b = r[i + lag];
      if (!std::isfinite(a) || !std::isfinite(b)) continue;
      s.lag_n[l] += 1, s.lag_sa[l] += a, s.lag_sb[l] += b, s.lag_sab[l] += a * b;
    }
  }
  const auto window = static_cast<std::size_t>(std::lround(kWarmingWindowS / (static_cast<double>(every) * cycle.dt_s)));
  for (std::size_t i = 0; i < n; ++i) {
    const double res = r[i];
    if (!std::isfinite(res)) continue;
    if (i >= window && std::isfinite(y[i]) && std::isfinite(y[i - window])) {
      const double w = (y[i] - y[i - window]) / (kWarmingWindowS / 60.0);  // K/min
      s.nw += 1, s.sw += w, s.sww += w * w, s.swr += w * res, s.srw += res, s.srrw += res * res;
    }
    const double ambient = cycle.at(Channel::ambient_c, i * every);
    if (std::isfinite(y[i]) && std::isfinite(ambient)) {
      const double u = y[i] - ambient;
      s.nu += 1, s.su += u, s.suu += u * u, s.sur += u * res, s.sru += res, s.srru += res * res;
    }
  }
}

}  // namespace

Shape shape(const WhereSums& s) {
  Shape out;
  out.mean_k = s.n > 0 ? s.sr / s.n : NAN;
  out.with_warming = correlation(s.nw, s.sw, s.sww, s.swr, s.srw, s.srrw);
  out.with_rise = correlation(s.nu, s.su, s.suu, s.sur, s.sru, s.srru);
  // The autocorrelation about the pooled mean, against the pooled variance: an offset that differs
  // between cycles counts as slow, which it is.
  const double mean = out.mean_k, var = s.n > 1 ? s.srr / s.n - mean * mean : NAN;
  out.correlation_time_s = NAN;
  if (!(var > 0)) return out;
  double prev_lag = 0, prev_rho = 1;
  for (std::size_t l = 0; l < kShapeLagsS.size() && std::isnan(out.correlation_time_s); ++l) {
    if (s.lag_n[l] < 30) {
      // Before any lag with pairs: shorter than the sensor's reading period (a sensor read every
      // 10 s has no pairs 1 s apart). After: the cycles are shorter than this lag.
      if (prev_lag == 0) continue;
      break;
    }
    const double rho = (s.lag_sab[l] / s.lag_n[l] - mean * (s.lag_sa[l] + s.lag_sb[l]) / s.lag_n[l] + mean * mean) / var;
    if (rho < kOneOverE)  // linear between the last lag above 1/e and this one
      out.correlation_time_s = prev_lag + (kShapeLagsS[l] - prev_lag) * (prev_rho - kOneOverE) / (prev_rho - rho);
    prev_lag = kShapeLagsS[l], prev_rho = rho;
  }
  if (std::isnan(out.correlation_time_s) && prev_lag > 0) {
    out.correlation_time_s = prev_lag;  // still above 1/e at the longest lag with pairs
    out.correlation_time_at_least = true;
  }
  out.effective_readings = s.n / std::max(1.0, 2 * out.correlation_time_s);  // readings at 1 Hz
  return out;
}

RegionEdges region_edges(const data::Dataset& dataset, const std::vector<std::size_t>& cycles) {
  RegionEdges e;
  const Channel channels[2] = {Channel::speed_rpm, Channel::current_a};
  std::array<double, 2>* edges[2] = {&e.speed, &e.current};
  std::array<double, 2>* ranges[2] = {&e.speed_range, &e.current_range};
  for (int c = 0; c < 2; ++c) {
    double lo = INFINITY, hi = -INFINITY;
    for (std::size_t i : cycles) {
      const data::Cycle& cycle = dataset.cycles[i];
      for (std::size_t k = 0; k < cycle.steps; k += one_hertz(cycle)) {
        const double x = std::abs(cycle.at(channels[c], k));
        if (std::isfinite(x)) lo = std::min(lo, x), hi = std::max(hi, x);
      }
    }
    if (!(hi > lo)) {
      *edges[c] = {lo, hi};
      *ranges[c] = {lo, hi};
      continue;
    }
    std::vector<double> hist(256, 0.0);
    for (std::size_t i : cycles) {
      const data::Cycle& cycle = dataset.cycles[i];
      for (std::size_t k = 0; k < cycle.steps; k += one_hertz(cycle)) {
        const double x = std::abs(cycle.at(channels[c], k));
        if (!std::isfinite(x)) continue;
        const auto bin = static_cast<std::size_t>((x - lo) / (hi - lo) * 255.999);
        hist[std::min<std::size_t>(bin, 255)] += 1;
      }
    }
    *edges[c] = {quantile(hist, lo, hi, 1.0 / 3), quantile(hist, lo, hi, 2.0 / 3)};
    *ranges[c] = {lo, hi};
  }
  return e;
}

WhereSums& WhereSums::operator+=(const WhereSums& o) {
  n += o.n, sr += o.sr, srr += o.srr;
  for (std::size_t i = 0; i < kShapeLagsS.size(); ++i)
    lag_n[i] += o.lag_n[i], lag_sa[i] += o.lag_sa[i], lag_sb[i] += o.lag_sb[i], lag_sab[i] += o.lag_sab[i];
  nw += o.nw, sw += o.sw, sww += o.sww, swr += o.swr, srw += o.srw, srrw += o.srrw;
  nu += o.nu, su += o.su, suu += o.suu, sur += o.sur, sru += o.sru, srru += o.srru;
  for (std::size_t i = 0; i < kFollowInputs; ++i) {
    n_in[i] += o.n_in[i], sx[i] += o.sx[i], sxx[i] += o.sxx[i], sxr[i] += o.sxr[i];
    sr_in[i] += o.sr_in[i], srr_in[i] += o.srr_in[i];
  }
  for (std::size_t i = 0; i < region_n.size(); ++i) region_n[i] += o.region_n[i], region_rr[i] += o.region_rr[i];
  return *this;
}

WhereSums where_sums(const data::Cycle& cycle, Channel sensor, const std::vector<float>& residual,
                     const RegionEdges& edges) {
  WhereSums s;
  add_shape_sums(s, cycle, sensor, residual);
  std::array<double, kFollowInputs> lagged{};
  std::array<bool, kFollowInputs> started{};
  const double alpha = std::min(1.0, cycle.dt_s / kFollowTauS);
  const std::size_t every = one_hertz(cycle);
  for (std::size_t k = 0; k < cycle.steps && k < residual.size(); ++k) {
    for (std::size_t i = 0; i < kFollowInputs; ++i) {
      const double x = cycle.at(kInputs[i].channel, k);
      if (!std::isfinite(x)) continue;
      lagged[i] = started[i] ? lagged[i] + alpha * (x - lagged[i]) : x;
      started[i] = true;
    }
    const double r = residual[k];
    if (k % every != 0 || !std::isfinite(r)) continue;
    s.n += 1, s.sr += r, s.srr += r * r;
    for (std::size_t i = 0; i < kFollowInputs; ++i) {
      if (!started[i]) continue;  // no reading of this input yet (or none at all)
      const double x = lagged[i];
      s.n_in[i] += 1, s.sx[i] += x, s.sxx[i] += x * x, s.sxr[i] += x * r, s.sr_in[i] += r, s.srr_in[i] += r * r;
    }
    const double speed = std::abs(cycle.at(Channel::speed_rpm, k)), current = std::abs(cycle.at(Channel::current_a, k));
    if (!std::isfinite(speed) || !std::isfinite(current)) continue;
    const auto cell = static_cast<std::size_t>(3 * tertile(speed, edges.speed) + tertile(current, edges.current));
    s.region_n[cell] += 1;
    s.region_rr[cell] += r * r;
  }
  return s;
}

Where where(const WhereSums& s, const RegionEdges& edges) {
  Where w;
  for (std::size_t i = 0; i < kFollowInputs; ++i) {
    const double r = correlation(s.n_in[i], s.sx[i], s.sxx[i], s.sxr[i], s.sr_in[i], s.srr_in[i]);
    if (std::abs(r) >= kFollowMin) w.follows.push_back({kInputs[i].name, r});
  }
  std::sort(w.follows.begin(), w.follows.end(),
            [](const Follows& a, const Follows& b) { return std::abs(a.correlation) > std::abs(b.correlation); });
  if (w.follows.size() > 3) w.follows.resize(3);

  double total = 0;
  for (double n : s.region_n) total += n;
  int worst = -1;
  for (int c = 0; c < 9; ++c) {
    const auto i = static_cast<std::size_t>(c);
    if (s.region_n[i] < kRegionMinShare * total || s.region_n[i] == 0) continue;
    if (worst < 0 || s.region_rr[i] / s.region_n[i] > s.region_rr[static_cast<std::size_t>(worst)] / s.region_n[static_cast<std::size_t>(worst)])
      worst = c;
  }
  if (worst >= 0 && total > 0) {
    const auto i = static_cast<std::size_t>(worst);
    static const char* kWords[3] = {"low", "middle", "high"};
    const auto bounds = [](const std::array<double, 2>& tertiles, const std::array<double, 2>& seen, int t) {
      return std::array<double, 2>{t == 0 ? seen[0] : tertiles[static_cast<std::size_t>(t - 1)],
                                   t == 2 ? seen[1] : tertiles[static_cast<std::size_t>(t)]};
    };
    const int ts = worst / 3, tc = worst % 3;
    w.region = range(kWords[ts], "speed", bounds(edges.speed, edges.speed_range, ts), "1/min") + ", " +
               range(kWords[tc], "current", bounds(edges.current, edges.current_range, tc), "A");
    w.region_rmse_k = std::sqrt(s.region_rr[i] / s.region_n[i]);
    w.region_share = s.region_n[i] / total;
  }
  return w;
}

}  // namespace lptn::diagnose::internal
