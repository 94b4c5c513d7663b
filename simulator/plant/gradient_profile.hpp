#pragma once
// The line's gradient as a function of distance travelled: piecewise constant sections drawn
// lazily as the train gets there.

#include <vector>

#include "simulator/plant/random.hpp"
#include "simulator/plant/route_profile.hpp"

namespace lptn::plant {

class GradientProfile {
 public:
  GradientProfile(const RouteProfile& route, std::uint64_t seed);

  // Gradient (rise / run, positive uphill in the direction of travel) at distance s >= 0.
  double grade_at(double distance_m);

 private:
  struct Section {
    double end_m;
    double grade;
  };
  void extend();

  RouteProfile route_;
  Rng rng_;
  std::vector<Section> sections_;
  double last_steep_sign_ = 1.0;
  std::size_t cursor_ = 0;  // lookups move forward almost always: start from the last hit
};

}  // namespace lptn::plant
