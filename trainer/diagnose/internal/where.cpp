#include "trainer/diagnose/internal/where.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

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

}  // namespace

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
  for (std::size_t i = 0; i < kFollowInputs; ++i) {
    n_in[i] += o.n_in[i], sx[i] += o.sx[i], sxx[i] += o.sxx[i], sxr[i] += o.sxr[i];
    sr_in[i] += o.sr_in[i], srr_in[i] += o.srr_in[i];
  }
  for (std::size_t i = 0; i < region_n.size(); ++i) region_n[i] += o.region_n[i], region_rr[i] += o.region_rr[i];
  return *this;
}

WhereSums where_sums(const data::Cycle& cycle, const std::vector<float>& residual, const RegionEdges& edges) {
  WhereSums s;
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
    const double n = s.n_in[i];
    if (n < 10) continue;
    const double vx = s.sxx[i] - s.sx[i] * s.sx[i] / n, vr = s.srr_in[i] - s.sr_in[i] * s.sr_in[i] / n;
    if (!(vx > 0) || !(vr > 0)) continue;
    const double r = (s.sxr[i] - s.sx[i] * s.sr_in[i] / n) / std::sqrt(vx * vr);
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
