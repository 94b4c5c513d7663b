#include "simulator/plant/blower.hpp"

#include <algorithm>
#include <cmath>

namespace lptn::plant {
namespace {

// load_following: the control runs the fan from a lagged load signal. It rises within a minute
// and falls over a few minutes, which gives the run-on after the train stops.
constexpr double kMinLevel = 0.35;
constexpr double kFullLevelAtLoad = 0.7;  // lagged |P| / P_rated at which the fan is at full speed
constexpr double kRiseTau_s = 60.0;
constexpr double kFallTau_s = 240.0;

// stepped: levels and hold times.
constexpr double kStepMinLevel = 0.3;
constexpr double kStepMaxLevel = 1.0;
constexpr double kStepMinHold_s = 480.0;
constexpr double kStepMaxHold_s = 900.0;
constexpr double kSpinUpTau_s = 10.0;

constexpr double kNoiseSigma = 0.004;  // fraction of nominal
constexpr double kNoiseTau_s = 20.0;

double lag(double x, double target, double dt_s, double tau_s) {
  return target + (x - target) * std::exp(-dt_s / tau_s);
}

}  // namespace

Blower::Blower(const BlowerPolicy& policy, double rated_power_w, std::uint64_t seed)
    : policy_(policy), rated_power_w_(rated_power_w), rng_(seed), noise_(kNoiseSigma, kNoiseTau_s) {
  if (policy_.mode == BlowerMode::stepped) {
    level_target_ = rng_.uniform(kStepMinLevel, kStepMaxLevel);
    level_ = level_target_;
    next_step_s_ = rng_.uniform(kStepMinHold_s, kStepMaxHold_s);
  }
}

double Blower::airflow_m3s() const {
  // The controlled modes stay inside their documented band; the noise only wobbles within it.
  double level = 0.0;
  switch (policy_.mode) {
    case BlowerMode::load_following:
      level = kMinLevel + (1.0 - kMinLevel) * std::min(1.0, load_ / kFullLevelAtLoad);
      level = std::clamp(level + noise_.value(), kMinLevel, 1.0);
      break;
    case BlowerMode::fixed: level = std::max(0.0, policy_.fixed_level + noise_.value()); break;
    case BlowerMode::stepped:
      level = std::clamp(level_ + noise_.value(), kStepMinLevel, kStepMaxLevel);
      break;
  }
  return policy_.nominal_airflow_m3s * level;
}

void Blower::advance(double dt_s, double mech_power_w) {
  noise_.advance(dt_s, rng_);
  switch (policy_.mode) {
    case BlowerMode::load_following: {
      const double target = std::min(1.0, std::abs(mech_power_w) / rated_power_w_);
      load_ = lag(load_, target, dt_s, target > load_ ? kRiseTau_s : kFallTau_s);
      break;
    }
    case BlowerMode::fixed: break;
    case BlowerMode::stepped:
      next_step_s_ -= dt_s;
      if (next_step_s_ <= 0.0) {
        level_target_ = rng_.uniform(kStepMinLevel, kStepMaxLevel);
        next_step_s_ += rng_.uniform(kStepMinHold_s, kStepMaxHold_s);
      }
      level_ = lag(level_, level_target_, dt_s, kSpinUpTau_s);
      break;
  }
}

}  // namespace lptn::plant
