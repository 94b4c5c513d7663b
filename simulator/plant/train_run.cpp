#include "simulator/plant/train_run.hpp"

#include <algorithm>
#include <cmath>

namespace lptn::plant {
namespace {

constexpr double kGravity = 9.81;
constexpr double kKmh = 1.0 / 3.6;
constexpr double kJerk_mps3 = 0.6;          // comfort limit on the change of acceleration
constexpr double kSpeedGain_per_s = 0.15;   // speed-holding gain: full effort until ~1 m/s short
constexpr double kBrakeReaction_s = 1.5;    // the brake builds up over ~this, so start earlier
constexpr double kStopMargin_m = 1.0;       // aim a little short of the stop mark
constexpr double kMaxBrake_mps2 = 1.3;      // what the driver will use to make the mark
constexpr double kCreepBrake_mps2 = 0.3;    // below 1 m/s: finish the stop instead of creeping
constexpr double kElectricFadeBand_kmh = 3.0;
constexpr double kOverspeedTolerance = 1.02;  // coasting stops when this far above the limit
constexpr double kRestrictionTrigger = 0.8;   // brake for a slow order at this share of the target decel

}  // namespace

TrainRun::TrainRun(CycleKind kind, const MotorSpec& motor, const TrainSpec& train, std::uint64_t seed)
    : motor_(motor),
      train_(train),
      route_(route_profile(kind)),
      rng_(derive_seed(seed, 0)),
      gradient_(route_, derive_seed(seed, 1)),
      force_noise_(0.02 * force_from_torque_n(train, rated_torque_nm(motor)), 4.0),
      speed_wobble_(1.0, 60.0) {
  // Start standing at a stop, partway through the dwell.
  dwell_left_s_ = rng_.uniform(5.0, 60.0);
}

void TrainRun::start_segment() {
  segment_ = draw_segment(route_, train_.service_brake_mps2, direction_, rng_);
  direction_ = segment_.direction;
  position_m_ = 0.0;
  braking_to_stop_ = false;
}

// Wheel-force the driver asks for (per motor, N, positive pushes along the direction of travel).
// balance_n is what running resistance and gradient take; a force equal to it holds the speed.
double TrainRun::desired_force_n(double v, double balance_n, double max_traction_n) {
  const double m_eff = effective_mass_kg(train_);
  const double brake = segment_.brake_mps2;

  // Stopping at the end of the segment: once the braking curve is reached, follow it exactly
  // (the deceleration that stops the train at the mark), latched until standstill.
  const double to_stop = segment_.length_m - position_m_;
  const double v2 = v * v;
  if (!braking_to_stop_ && v > 0.0 &&
      v2 / (2.0 * std::max(to_stop - kStopMargin_m - v * kBrakeReaction_s, 0.25)) >= brake) {
    braking_to_stop_ = true;
  }
  if (braking_to_stop_) {
    double a = v2 / (2.0 * std::max(to_stop - kStopMargin_m, 0.25));
    if (v < 1.0) a = std::max(a, kCreepBrake_mps2);
    return balance_n - m_eff * std::min(a, kMaxBrake_mps2);
  }

  // Slow orders ahead: brake on their curve so as to enter them at the limit.
  double restriction_brake = 0.0;
  double limit = segment_.line_speed_mps;
  for (const SpeedRestriction& r : segment_.restrictions) {
    if (position_m_ >= r.start_m && position_m_ < r.end_m) limit = std::min(limit, r.limit_mps);
    if (r.start_m > position_m_ && v > r.limit_mps) {
      const double d = r.start_m - position_m_;
      const double dv2 = v2 - r.limit_mps * r.limit_mps;
      if (dv2 / (2.0 * std::max(d - v * kBrakeReaction_s, 1.0)) >= kRestrictionTrigger * brake) {
        restriction_brake = std::max(restriction_brake, dv2 / (2.0 * std::max(d, 1.0)));
      }
    }
  }
  if (restriction_brake > 0.0) return balance_n - m_eff * std::min(restriction_brake, kMaxBrake_mps2);

  // Coast for a while before the braking point, unless that would run away downhill.
  const double braking_distance = v2 / (2.0 * brake) + v * kBrakeReaction_s;
  if (to_stop - braking_distance < segment_.coast_m && v > 0.5 * limit &&
      v < kOverspeedTolerance * limit) {
    return 0.0;
  }

  // Hold (or reach) the limit: the balance force plus a speed correction, which saturates at the
  // driver's share of the available effort while accelerating; small hand noise on top.
  const double target = limit * (1.0 + 0.008 * std::clamp(speed_wobble_.value(), -2.0, 2.0));
  const double f = balance_n + m_eff * kSpeedGain_per_s * (target - v) + force_noise_.value();
  return std::clamp(f, balance_n - m_eff * brake, max_traction_n);
}

TrainRun::Command TrainRun::step(double h_s) {
  if (dwell_left_s_ > 0.0) {
    demand_n_ = 0.0;
    dwell_left_s_ -= h_s;
    if (dwell_left_s_ <= 0.0) start_segment();
    return {0.0, 0.0, false};
  }

  const double v = speed_mps_;
  const double grade = gradient_.grade_at(track_position_m_);
  const double balance = running_resistance_n(train_, v) + train_.mass_per_motor_kg * kGravity * grade;
  const double rpm = motor_rpm_from_speed(train_, v);
  const double torque_limit = torque_limit_nm(motor_, rpm);
  const double force_limit = force_from_torque_n(train_, torque_limit);

  force_noise_.advance(h_s, rng_);
  speed_wobble_.advance(h_s, rng_);
  const double desired = desired_force_n(v, balance, segment_.traction_fraction * force_limit);

  // Jerk limit on the total demand (traction and brakes alike).
  const double m_eff = effective_mass_kg(train_);
  const double max_change = kJerk_mps3 * m_eff * h_s;
  demand_n_ += std::clamp(desired - demand_n_, -max_change, max_change);

  // Traction is all electric. Braking is electric up to the motor's limit and above the fade-out
  // speed; the mechanical brake supplies the rest (it heats no motor, so it does not appear).
  double electric_n = 0.0;
  if (demand_n_ >= 0.0) {
    electric_n = std::min(demand_n_, force_limit);
  } else {
    const double fade = std::clamp(
        (v / kKmh - train_.electric_brake_min_kmh) / kElectricFadeBand_kmh, 0.0, 1.0);
    // fade == 0 would leave -0.0, which flips the sign of torque * speed products downstream.
    electric_n = fade > 0.0 ? std::max(demand_n_, -force_limit) * fade : 0.0;
  }
  const double torque =
      std::clamp(torque_from_force_nm(train_, electric_n), -torque_limit, torque_limit);
  const double applied_n = demand_n_ >= 0.0 ? force_from_torque_n(train_, torque) : demand_n_;

  // Newton per motor; the brakes never push the train backwards.
  double v_next = v + (applied_n - balance) / m_eff * h_s;
  if (v_next <= 0.0) v_next = 0.0;
  const double advanced = 0.5 * (v + v_next) * h_s;
  position_m_ += advanced;
  track_position_m_ += advanced;
  speed_mps_ = v_next;

  if (braking_to_stop_ && v_next == 0.0) {
    demand_n_ = 0.0;
    dwell_left_s_ = segment_.dwell_after_s;
  }
  return {direction_ * rpm, direction_ * torque, true};
}

}  // namespace lptn::plant
