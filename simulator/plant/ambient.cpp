#include "simulator/plant/ambient.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace lptn::plant {
namespace {

constexpr double kDriftMinAmplitude_k = 1.0;
constexpr double kDriftMinPeriod_s = 3.0 * 3600.0;  // a few K per hour at most
constexpr double kDriftMaxPeriod_s = 8.0 * 3600.0;
constexpr double kWanderSigma_k = 0.15;
constexpr double kWanderTau_s = 600.0;
constexpr double kMeanTunnelSpacing_s = 900.0;      // of moving time
constexpr double kTunnelMinLength_s = 45.0;
constexpr double kTunnelMaxLength_s = 150.0;
constexpr double kTunnelMinDepth_k = 2.0;
constexpr double kTunnelEnterTau_s = 20.0;
constexpr double kTunnelLeaveTau_s = 40.0;

}  // namespace

Ambient::Ambient(bool tunnels, std::uint64_t seed)
    : rng_(seed),
      tunnels_(tunnels),
      base_c_(rng_.uniform(kAmbientBaseMin_c, kAmbientBaseMax_c)),
      drift_amplitude_k_(rng_.uniform(kDriftMinAmplitude_k, kAmbientDriftMax_k)),
      drift_period_s_(rng_.uniform(kDriftMinPeriod_s, kDriftMaxPeriod_s)),
      drift_phase_(rng_.uniform(0.0, 2.0 * std::numbers::pi)),
      wander_(kWanderSigma_k, kWanderTau_s) {
  to_next_tunnel_s_ = -kMeanTunnelSpacing_s * std::log(1.0 - rng_.uniform());
}

double Ambient::value_c() const {
  const double drift =
      drift_amplitude_k_ * std::sin(2.0 * std::numbers::pi * t_s_ / drift_period_s_ + drift_phase_);
  const double wander = std::clamp(wander_.value(), -kAmbientWanderMax_k, kAmbientWanderMax_k);
  return base_c_ + drift + wander + tunnel_offset_k_;
}

void Ambient::advance(double dt_s, bool moving) {
  t_s_ += dt_s;
  wander_.advance(dt_s, rng_);
  if (tunnels_) {
    if (tunnel_left_s_ > 0.0) {
      tunnel_left_s_ -= dt_s;
    } else if (moving) {
      to_next_tunnel_s_ -= dt_s;
      if (to_next_tunnel_s_ <= 0.0) {
        tunnel_left_s_ = rng_.uniform(kTunnelMinLength_s, kTunnelMaxLength_s);
        tunnel_depth_k_ = rng_.uniform(kTunnelMinDepth_k, kTunnelDepthMax_k);
        to_next_tunnel_s_ = -kMeanTunnelSpacing_s * std::log(1.0 - rng_.uniform());
      }
    }
  }
  const bool inside = tunnel_left_s_ > 0.0;
  const double target = inside ? -tunnel_depth_k_ : 0.0;
  const double tau = inside ? kTunnelEnterTau_s : kTunnelLeaveTau_s;
  tunnel_offset_k_ = target + (tunnel_offset_k_ - target) * std::exp(-dt_s / tau);
}

}  // namespace lptn::plant
