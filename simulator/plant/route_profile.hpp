#pragma once
// The numbers that make one kind of service differ from another: stop spacing, line speed,
// dwell, driving style, gradients, speed restrictions. Everything random is drawn from these ranges.

#include "simulator/plant/cycle_kind.hpp"

namespace lptn::plant {

struct Range {
  double lo;
  double hi;
};

struct RouteProfile {
  Range spacing_m;               // distance between stops (a shunting move's length)
  Range line_speed_kmh;
  Range dwell_s;                 // standing time at a stop
  double long_dwell_probability; // chance that a stop is a long idle instead (shunting)
  Range long_dwell_s;
  Range coast_m;                 // coasting before the braking point
  Range traction_fraction;       // share of the available tractive effort the driver uses
  double brake_mps2;             // target braking; <= 0 means the train's service brake
  double reversal_probability;   // chance to change direction at a stop
  // Gradient sections: length, then either a steep grade of random sign or a mild one.
  Range grade_section_m;
  double steep_grade_probability;
  Range steep_grade_pct;
  double mild_grade_pct;         // mild grades are uniform in +-this
  double steep_sign_persistence; // chance a steep section keeps the previous one's sign (long ramps)
  // Speed restrictions (slow orders): expected number per km, their length and limit.
  double restrictions_per_km;
  Range restriction_length_m;
  Range restriction_speed_factor;  // limit as a fraction of the line speed
  bool tunnels;                  // whether the ambient sees tunnels
};

RouteProfile route_profile(CycleKind kind);

}  // namespace lptn::plant
