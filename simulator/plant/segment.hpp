#pragma once
// One run from a stop to the next (a move, when shunting): what the driver knows before starting.

#include <vector>

#include "simulator/plant/random.hpp"
#include "simulator/plant/route_profile.hpp"

namespace lptn::plant {

struct SpeedRestriction {
  double start_m;  // from the start of the segment
  double end_m;
  double limit_mps;
};

struct Segment {
  double length_m;
  double line_speed_mps;
  double coast_m;            // distance coasted before the braking point
  double traction_fraction;  // share of the available tractive effort used
  double brake_mps2;
  double dwell_after_s;      // standing time at the stop that ends the segment
  int direction;             // +1 forward, -1 reverse (shunting)
  std::vector<SpeedRestriction> restrictions;  // sorted, non-overlapping
};

Segment draw_segment(const RouteProfile& route, double service_brake_mps2, int previous_direction,
                     Rng& rng);

}  // namespace lptn::plant
