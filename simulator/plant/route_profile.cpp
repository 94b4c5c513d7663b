#include "simulator/plant/route_profile.hpp"

namespace lptn::plant {

RouteProfile route_profile(CycleKind kind) {
  // Shared base: a passenger line with mild gradients and the occasional slow order.
  RouteProfile r{.spacing_m = {4000.0, 10000.0},
                 .line_speed_kmh = {120.0, 140.0},
                 .dwell_s = {30.0, 90.0},
                 .long_dwell_probability = 0.0,
                 .long_dwell_s = {0.0, 0.0},
                 .coast_m = {300.0, 1200.0},
                 .traction_fraction = {1.0, 1.0},
                 .brake_mps2 = 0.0,
                 .reversal_probability = 0.0,
                 .grade_section_m = {1000.0, 4000.0},
                 .steep_grade_probability = 0.0,
                 .steep_grade_pct = {0.0, 0.0},
                 .mild_grade_pct = 0.5,
                 .steep_sign_persistence = 0.5,
                 .restrictions_per_km = 0.04,
                 .restriction_length_m = {300.0, 1500.0},
                 .restriction_speed_factor = {0.4, 0.7},
                 .tunnels = true};
  switch (kind) {
    case CycleKind::suburban:
      r.spacing_m = {1500.0, 3000.0};
      r.line_speed_kmh = {80.0, 100.0};
      r.dwell_s = {30.0, 60.0};
      r.coast_m = {100.0, 400.0};
      r.restriction_length_m = {200.0, 600.0};
      break;
    case CycleKind::regional:
      break;
    case CycleKind::intercity:
      r.spacing_m = {15000.0, 40000.0};
      r.line_speed_kmh = {160.0, 160.0};
      r.dwell_s = {60.0, 180.0};
      r.coast_m = {500.0, 2500.0};
      r.restriction_speed_factor = {0.5, 0.75};
      break;
    case CycleKind::hilly:
      // Regional spacing on a mountain line: km-long climbs and descents of 1.5-3.5 %.
      // Consecutive steep sections mostly keep their sign: ramps several km long, so trains start
      // from stations on the climb and spend minutes at full effort.
      r.line_speed_kmh = {120.0, 140.0};
      r.coast_m = {200.0, 800.0};
      r.grade_section_m = {800.0, 3000.0};
      r.steep_grade_probability = 0.8;
      r.steep_grade_pct = {1.5, 3.5};
      r.steep_sign_persistence = 0.75;
      break;
    case CycleKind::shunting:
      // Depot moves: short, slow, gentle, with long idles and frequent reversals; flat, no tunnels.
      r.spacing_m = {100.0, 600.0};
      r.line_speed_kmh = {10.0, 25.0};
      r.dwell_s = {20.0, 180.0};
      r.long_dwell_probability = 0.2;
      r.long_dwell_s = {300.0, 900.0};
      r.coast_m = {0.0, 0.0};
      r.traction_fraction = {0.3, 0.6};
      r.brake_mps2 = 0.5;
      r.reversal_probability = 0.6;
      r.mild_grade_pct = 0.0;
      r.restrictions_per_km = 0.0;
      r.tunnels = false;
      break;
  }
  return r;
}

}  // namespace lptn::plant
