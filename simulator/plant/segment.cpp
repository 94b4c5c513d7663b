#include "simulator/plant/segment.hpp"

#include <algorithm>
#include <cmath>

namespace lptn::plant {
namespace {

constexpr double kKmh = 1.0 / 3.6;
constexpr double kClearOfStops_m = 500.0;     // slow orders keep away from the platforms
constexpr double kMinRestriction_kmh = 20.0;

// Slow orders: each km of the segment may start one, at a random point within it.
std::vector<SpeedRestriction> draw_restrictions(const RouteProfile& route, double length_m,
                                                double line_speed_kmh, Rng& rng) {
  std::vector<SpeedRestriction> out;
  if (route.restrictions_per_km <= 0.0) return out;
  double km_start = kClearOfStops_m;
  while (km_start + 1000.0 < length_m - kClearOfStops_m) {
    if (rng.chance(route.restrictions_per_km)) {
      const double start = km_start + rng.uniform(0.0, 1000.0);
      const double len = rng.uniform(route.restriction_length_m.lo, route.restriction_length_m.hi);
      const double end = std::min(start + len, length_m - kClearOfStops_m);
      const double factor =
          rng.uniform(route.restriction_speed_factor.lo, route.restriction_speed_factor.hi);
      // Signs show multiples of 5 km/h.
      const double limit_kmh = std::max(kMinRestriction_kmh, 5.0 * std::round(factor * line_speed_kmh / 5.0));
      if (end > start) out.push_back({start, end, limit_kmh * kKmh});
      km_start = std::max(km_start + 1000.0, end);
    } else {
      km_start += 1000.0;
    }
  }
  return out;
}

}  // namespace

Segment draw_segment(const RouteProfile& route, double service_brake_mps2, int previous_direction,
                     Rng& rng) {
  Segment s;
  s.length_m = rng.uniform(route.spacing_m.lo, route.spacing_m.hi);
  const double line_kmh = rng.uniform(route.line_speed_kmh.lo, route.line_speed_kmh.hi);
  s.line_speed_mps = line_kmh * kKmh;
  s.coast_m = rng.uniform(route.coast_m.lo, route.coast_m.hi);
  s.traction_fraction = rng.uniform(route.traction_fraction.lo, route.traction_fraction.hi);
  s.brake_mps2 = route.brake_mps2 > 0.0 ? route.brake_mps2 : service_brake_mps2;
  s.dwell_after_s = rng.chance(route.long_dwell_probability)
                        ? rng.uniform(route.long_dwell_s.lo, route.long_dwell_s.hi)
                        : rng.uniform(route.dwell_s.lo, route.dwell_s.hi);
  s.direction = rng.chance(route.reversal_probability) ? -previous_direction : previous_direction;
  s.restrictions = draw_restrictions(route, s.length_m, line_kmh, rng);
  return s;
}

}  // namespace lptn::plant
