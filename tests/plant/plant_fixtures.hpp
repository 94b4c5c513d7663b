#pragma once
// The project's example motor and the summary statistics the cycle tests reason about.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

#include "simulator/plant/driving_cycle.hpp"
#include "simulator/plant/motor_spec.hpp"
#include "simulator/plant/train_spec.hpp"

namespace lptn::plant::test {

// 4-pole, 65 Hz, 1900 V, 115 A, 310 kW (the example motor file).
inline MotorSpec example_motor() {
  MotorSpec m{};
  m.pole_pairs = 2;
  m.rated_frequency_hz = 65.0;
  m.rated_voltage_v = 1900.0;
  m.rated_current_a = 115.0;
  m.rated_power_w = 310e3;
  m.stator_resistance_20c_ohm = 0.14;
  m.stator_resistance_alpha_per_k = 0.00393;
  m.rotor_resistance_20c_ohm = 0.10;
  m.rotor_resistance_alpha_per_k = 0.0039;
  m.magnetizing_current_a = 40.0;
  return m;
}

struct CycleStats {
  double max_speed_kmh = 0.0;
  double stops_per_hour = 0.0;
  double standstill_share = 0.0;
  double longest_full_torque_s = 0.0;  // longest run of |T| >= 95 % of the limit
  double full_torque_share = 0.0;
};

inline constexpr double kStandstill_rpm = 0.5;
inline constexpr double kMinStop_s = 10.0;

inline CycleStats cycle_stats(const std::vector<DriveSample>& cycle, const MotorSpec& motor,
                              const TrainSpec& train) {
  CycleStats s;
  if (cycle.size() < 2) return s;
  const double dt = cycle[1].t_s - cycle[0].t_s;
  std::size_t standing = 0, full = 0, stops = 0;
  double run_standing = 0.0, run_full = 0.0;
  bool moved = false, counted = false;
  for (const DriveSample& x : cycle) {
    s.max_speed_kmh = std::max(s.max_speed_kmh, 3.6 * speed_mps_from_motor_rpm(train, std::abs(x.speed_rpm)));
    if (std::abs(x.speed_rpm) < kStandstill_rpm) {
      ++standing;
      run_standing += dt;
      if (moved && !counted && run_standing >= kMinStop_s) {
        ++stops;
        counted = true;
      }
    } else {
      moved = true;
      counted = false;
      run_standing = 0.0;
    }
    if (std::abs(x.torque_nm) >= 0.95 * torque_limit_nm(motor, x.speed_rpm) && x.torque_nm * x.speed_rpm >= 0.0) {
      ++full;
      run_full += dt;
      s.longest_full_torque_s = std::max(s.longest_full_torque_s, run_full);
    } else {
      run_full = 0.0;
    }
  }
  const double hours = (cycle.back().t_s - cycle.front().t_s) / 3600.0;
  s.stops_per_hour = static_cast<double>(stops) / hours;
  s.standstill_share = static_cast<double>(standing) / static_cast<double>(cycle.size());
  s.full_torque_share = static_cast<double>(full) / static_cast<double>(cycle.size());
  return s;
}

inline double mech_power_w(const DriveSample& x) {
  return x.torque_nm * x.speed_rpm * 2.0 * std::numbers::pi / 60.0;
}

// Trailing mean over `window` samples (fewer at the start): the "recent load".
inline std::vector<double> trailing_mean(const std::vector<double>& x, std::size_t window) {
  std::vector<double> y(x.size());
  double acc = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    acc += x[i];
    if (i >= window) acc -= x[i - window];
    y[i] = acc / static_cast<double>(std::min(i + 1, window));
  }
  return y;
}

// Pearson correlation of two equally long series.
inline double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const auto n = static_cast<double>(a.size());
  double ma = 0.0, mb = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ma += a[i];
    mb += b[i];
  }
  ma /= n;
  mb /= n;
  double sab = 0.0, saa = 0.0, sbb = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

}  // namespace lptn::plant::test
