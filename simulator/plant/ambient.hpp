#pragma once
// Air temperature around the motor over a cycle: a seeded base, a slow drift, tunnels.

#include <cstdint>

#include "simulator/plant/random.hpp"

namespace lptn::plant {

// Bounds: base in [-10, 35] C, drift amplitude <= 3 K, weather wander clamped to +-0.5 K,
// tunnels <= 5 K colder, so ambient always stays within [-18.5, 38.5] C.
inline constexpr double kAmbientBaseMin_c = -10.0;
inline constexpr double kAmbientBaseMax_c = 35.0;
inline constexpr double kAmbientDriftMax_k = 3.0;
inline constexpr double kAmbientWanderMax_k = 0.5;
inline constexpr double kTunnelDepthMax_k = 5.0;

class Ambient {
 public:
  Ambient(bool tunnels, std::uint64_t seed);

  double value_c() const;

  // Moves time on; tunnels are only entered while the train is moving.
  void advance(double dt_s, bool moving);

 private:
  Rng rng_;
  bool tunnels_;
  double base_c_;
  double drift_amplitude_k_;
  double drift_period_s_;
  double drift_phase_;
  OuNoise wander_;
  double t_s_ = 0.0;
  double to_next_tunnel_s_ = 0.0;  // moving time until the next tunnel portal
  double tunnel_left_s_ = 0.0;     // > 0 while inside
  double tunnel_depth_k_ = 0.0;
  double tunnel_offset_k_ = 0.0;   // lagged: air in a tunnel cools and recovers over tens of s
};

}  // namespace lptn::plant
