#include "tools/report/stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lptn::report {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double mean_of(const Segments& s) {
  double sum = 0;
  std::size_t n = 0;
  for (const auto& seg : s) {
    for (double v : seg) {
      if (std::isnan(v)) continue;
      sum += v;
      ++n;
    }
  }
  return n ? sum / static_cast<double>(n) : kNaN;
}

// sum over segments and valid pairs of (a_t - ma)(b_{t+lag} - mb); lag may be negative.
double lagged_product(const Segments& a, double ma, const Segments& b, double mb, std::ptrdiff_t lag) {
  double sum = 0;
  for (std::size_t s = 0; s < a.size(); ++s) {
    const auto& x = a[s];
    const auto& y = b[s];
    const auto n = static_cast<std::ptrdiff_t>(std::min(x.size(), y.size()));
    for (std::ptrdiff_t t = std::max<std::ptrdiff_t>(0, -lag); t < n && t + lag < n; ++t) {
      const double u = x[static_cast<std::size_t>(t)], v = y[static_cast<std::size_t>(t + lag)];
      if (!std::isnan(u) && !std::isnan(v)) sum += (u - ma) * (v - mb);
    }
  }
  return sum;
}

std::size_t bin_index(double v, const std::vector<double>& edges) {
  const auto it = std::upper_bound(edges.begin() + 1, edges.end() - 1, v);
  return static_cast<std::size_t>(it - (edges.begin() + 1));
}

void add(Bin& b, double e) {
  ++b.n;
  b.mean += e;
  b.rmse += e * e;
}

void finish(Bin& b) {
  if (b.n == 0) {
    b.mean = b.rmse = kNaN;
    return;
  }
  b.mean /= static_cast<double>(b.n);
  b.rmse = std::sqrt(b.rmse / static_cast<double>(b.n));
}

std::vector<Bin> empty_bins(const std::vector<double>& edges) {
  std::vector<Bin> bins(edges.size() - 1);
  for (std::size_t i = 0; i < bins.size(); ++i) {
    bins[i].lo = edges[i];
    bins[i].hi = edges[i + 1];
  }
  return bins;
}

Window window_at(const std::vector<double>& e, std::size_t segment, std::size_t start, std::size_t length) {
  Window w{segment, start, length, 0, 0};
  for (std::size_t t = start; t < start + length; ++t) {
    if (std::isnan(e[t])) continue;
    w.rmse += e[t] * e[t];
    ++w.n;
  }
  w.rmse = w.n ? std::sqrt(w.rmse / static_cast<double>(w.n)) : kNaN;
  return w;
}

bool overlaps(const Window& a, const Window& b) {
  return a.segment == b.segment && a.start < b.start + b.length && b.start < a.start + a.length;
}

}  // namespace

std::vector<double> block_means(const std::vector<float>& samples, std::size_t block) {
  std::vector<double> out;
  out.reserve(samples.size() / block + 1);
  for (std::size_t i = 0; i < samples.size(); i += block) {
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t k = i; k < std::min(samples.size(), i + block); ++k) {
      if (std::isnan(samples[k])) continue;
      sum += samples[k];
      ++n;
    }
    out.push_back(n ? sum / static_cast<double>(n) : kNaN);
  }
  return out;
}

Envelope envelope(const std::vector<float>& samples, std::size_t bucket) {
  Envelope env;
  for (std::size_t i = 0; i < samples.size(); i += bucket) {
    double lo = kNaN, hi = kNaN, sum = 0;
    std::size_t n = 0;
    for (std::size_t k = i; k < std::min(samples.size(), i + bucket); ++k) {
      const double v = samples[k];
      if (std::isnan(v)) continue;
      lo = n ? std::min(lo, v) : v;
      hi = n ? std::max(hi, v) : v;
      sum += v;
      ++n;
    }
    env.lo.push_back(lo);
    env.mean.push_back(n ? sum / static_cast<double>(n) : kNaN);
    env.hi.push_back(hi);
  }
  return env;
}

std::vector<double> autocorrelation(const Segments& e, std::size_t max_lag) {
  const double m = mean_of(e);
  const double c0 = lagged_product(e, m, e, m, 0);
  std::vector<double> r(max_lag + 1, kNaN);
  if (!(c0 > 0)) return r;
  for (std::size_t k = 0; k <= max_lag; ++k) r[k] = lagged_product(e, m, e, m, static_cast<std::ptrdiff_t>(k)) / c0;
  return r;
}

std::vector<double> cross_correlation(const Segments& x, const Segments& e, std::size_t max_lag) {
  const double mx = mean_of(x), me = mean_of(e);
  const double norm = std::sqrt(lagged_product(x, mx, x, mx, 0) * lagged_product(e, me, e, me, 0));
  std::vector<double> r(2 * max_lag + 1, kNaN);
  if (!(norm > 0)) return r;
  const auto lag_max = static_cast<std::ptrdiff_t>(max_lag);
  for (std::ptrdiff_t k = -lag_max; k <= lag_max; ++k)
    r[static_cast<std::size_t>(k + lag_max)] = lagged_product(x, mx, e, me, k) / norm;
  return r;
}

std::size_t valid_count(const Segments& e) {
  std::size_t n = 0;
  for (const auto& seg : e) n += static_cast<std::size_t>(std::count_if(seg.begin(), seg.end(), [](double v) { return !std::isnan(v); }));
  return n;
}

double rms(const Segments& e) {
  double sum = 0;
  std::size_t n = 0;
  for (const auto& seg : e) {
    for (double v : seg) {
      if (std::isnan(v)) continue;
      sum += v * v;
      ++n;
    }
  }
  return n ? std::sqrt(sum / static_cast<double>(n)) : kNaN;
}

double white_noise_band(std::size_t n) { return n ? 1.96 / std::sqrt(static_cast<double>(n)) : kNaN; }

double bartlett_band(std::size_t n, const std::vector<double>& acf_x, const std::vector<double>& acf_e) {
  double factor = 1;  // k = 0; the sum is symmetric in k
  for (std::size_t k = 1; k < std::min(acf_x.size(), acf_e.size()); ++k) {
    if (!std::isnan(acf_x[k]) && !std::isnan(acf_e[k])) factor += 2 * acf_x[k] * acf_e[k];
  }
  return white_noise_band(n) * std::sqrt(std::max(1.0, factor));
}

std::vector<Bin> bin_residuals(const std::vector<double>& x, const std::vector<double>& e,
                               const std::vector<double>& edges) {
  std::vector<Bin> bins = empty_bins(edges);
  for (std::size_t i = 0; i < std::min(x.size(), e.size()); ++i) {
    if (!std::isnan(x[i]) && !std::isnan(e[i])) add(bins[bin_index(x[i], edges)], e[i]);
  }
  for (Bin& b : bins) finish(b);
  return bins;
}

std::vector<std::vector<Bin>> bin_residuals_2d(const std::vector<double>& x, const std::vector<double>& y,
                                               const std::vector<double>& e, const std::vector<double>& x_edges,
                                               const std::vector<double>& y_edges) {
  std::vector<std::vector<Bin>> grid(x_edges.size() - 1, empty_bins(y_edges));
  for (std::size_t i = 0; i < std::min({x.size(), y.size(), e.size()}); ++i) {
    if (std::isnan(x[i]) || std::isnan(y[i]) || std::isnan(e[i])) continue;
    add(grid[bin_index(x[i], x_edges)][bin_index(y[i], y_edges)], e[i]);
  }
  for (auto& row : grid) {
    for (Bin& b : row) finish(b);
  }
  return grid;
}

std::vector<double> linear_edges(double lo, double hi, std::size_t count) {
  if (!(hi > lo)) hi = lo + 1;
  std::vector<double> edges(count + 1);
  for (std::size_t i = 0; i <= count; ++i) edges[i] = lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(count);
  return edges;
}

std::vector<double> aligned_edges(double lo, double hi, double step) {
  const double first = std::floor(lo / step) * step;
  std::vector<double> edges{first};
  while (edges.back() < hi || edges.size() < 2) edges.push_back(edges.back() + step);
  return edges;
}

std::vector<double> quantile_edges(const std::vector<double>& x, std::size_t count) {
  std::vector<double> v;
  for (double d : x) {
    if (!std::isnan(d)) v.push_back(d);
  }
  if (v.empty()) return {0, 1};
  std::sort(v.begin(), v.end());
  std::vector<double> edges;
  for (std::size_t i = 0; i <= count; ++i) {
    const double q = v[std::min(v.size() - 1, i * (v.size() - 1) / count)];
    if (edges.empty() || q > edges.back()) edges.push_back(q);
  }
  if (edges.size() < 2) edges.push_back(edges.back() + 1);
  return edges;
}

std::vector<Window> worst_windows(const Segments& e, std::size_t length, std::size_t stride, std::size_t count) {
  std::vector<Window> candidates;
  for (std::size_t s = 0; s < e.size(); ++s) {
    for (std::size_t start = 0; start + length <= e[s].size(); start += stride) {
      const Window w = window_at(e[s], s, start, length);
      if (2 * w.n >= length) candidates.push_back(w);
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Window& a, const Window& b) { return a.rmse > b.rmse; });
  std::vector<Window> chosen;
  for (const Window& w : candidates) {
    if (chosen.size() == count) break;
    if (std::none_of(chosen.begin(), chosen.end(), [&](const Window& c) { return overlaps(c, w); })) chosen.push_back(w);
  }
  return chosen;
}

Range valid_range(const std::vector<double>& x) {
  Range r{kNaN, kNaN};
  for (double v : x) {
    if (std::isnan(v)) continue;
    r.lo = std::isnan(r.lo) ? v : std::min(r.lo, v);
    r.hi = std::isnan(r.hi) ? v : std::max(r.hi, v);
  }
  return r;
}

}  // namespace lptn::report
