#pragma once
// The motor's forced-ventilation blower: how much cooling air it delivers over a cycle.

#include <cstdint>

#include "simulator/plant/random.hpp"

namespace lptn::plant {

enum class BlowerMode {
  load_following,  // airflow follows the recent motor load (0.35..1.0 of nominal, with run-on)
  fixed,           // constant level (tiny fan noise)
  stepped,         // random level 0.3..1.0 every 8-15 min, independent of the load
};

struct BlowerPolicy {
  BlowerMode mode = BlowerMode::load_following;
  double fixed_level = 1.0;  // fraction of nominal airflow (fixed mode)
  double nominal_airflow_m3s = 1.0;
};

class Blower {
 public:
  Blower(const BlowerPolicy& policy, double rated_power_w, std::uint64_t seed);

  double airflow_m3s() const;

  // Moves the blower on by dt_s while the motor delivers mech_power_w (either sign).
  void advance(double dt_s, double mech_power_w);

 private:
  BlowerPolicy policy_;
  double rated_power_w_;
  Rng rng_;
  OuNoise noise_;
  double load_ = 0.0;          // load_following: lagged |power| / rated
  double level_ = 0.0;         // stepped: present level (fan spin-up lag)
  double level_target_ = 0.0;  // stepped: commanded level
  double next_step_s_ = 0.0;   // stepped: time to the next change
};

}  // namespace lptn::plant
