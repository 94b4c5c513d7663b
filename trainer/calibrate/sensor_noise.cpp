#include "trainer/calibrate/sensor_noise.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lptn::calibrate {
namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

double NoiseSum::sigma() const { return n ? std::sqrt(sum2 / static_cast<double>(n) / 1.5) : kNaN; }

NoiseSum sensor_noise(const std::vector<float>& e, std::size_t period) {
  const std::size_t p = std::max<std::size_t>(1, period);
  std::vector<NoiseSum> phase(p);
  for (std::size_t k = p; k + p < e.size(); ++k) {
    const double d = static_cast<double>(e[k]) - 0.5 * (static_cast<double>(e[k - p]) + static_cast<double>(e[k + p]));
    if (std::isnan(d)) continue;
    phase[k % p].sum2 += d * d;
    ++phase[k % p].n;
  }
  NoiseSum best;
  for (const NoiseSum& s : phase) {
    if (s.n && (!best.n || s.sum2 / static_cast<double>(s.n) > best.sum2 / static_cast<double>(best.n))) best = s;
  }
  return best;
}

std::size_t reading_period(const data::Dataset& dataset, const data::Cycle& cycle, data::Channel c) {
  for (const data::CycleReport& r : dataset.reports) {
    if (r.file != cycle.file) continue;
    const double rate = r.channels[data::index_of(c)].native_rate_hz;
    if (rate > 0) return std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(1 / (rate * cycle.dt_s))));
  }
  return 1;
}

}  // namespace lptn::calibrate
