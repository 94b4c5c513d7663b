#include "simulator/plant/train_spec.hpp"

#include <numbers>

namespace lptn::plant {
namespace {
constexpr double kRpmToRadPerS = 2.0 * std::numbers::pi / 60.0;
}  // namespace

double gear_ratio_for_top_speed(const MotorSpec& motor, double wheel_diameter_m, double top_speed_kmh) {
  const double wheel_rad_per_s = (top_speed_kmh / 3.6) / (0.5 * wheel_diameter_m);
  return max_speed_rpm(motor) * kRpmToRadPerS / wheel_rad_per_s;
}

TrainSpec default_train_spec(const MotorSpec& motor, double top_speed_kmh) {
  TrainSpec train;
  train.gear_ratio = gear_ratio_for_top_speed(motor, train.wheel_diameter_m, top_speed_kmh);
  return train;
}

double effective_mass_kg(const TrainSpec& train) {
  return train.mass_per_motor_kg * train.rotating_mass_factor;
}

double motor_rpm_from_speed(const TrainSpec& train, double speed_mps) {
  return speed_mps / (0.5 * train.wheel_diameter_m) * train.gear_ratio / kRpmToRadPerS;
}

double speed_mps_from_motor_rpm(const TrainSpec& train, double motor_rpm) {
  return motor_rpm * kRpmToRadPerS / train.gear_ratio * (0.5 * train.wheel_diameter_m);
}

double force_from_torque_n(const TrainSpec& train, double torque_nm) {
  return torque_nm * train.gear_ratio / (0.5 * train.wheel_diameter_m);
}

double torque_from_force_nm(const TrainSpec& train, double force_n) {
  return force_n * (0.5 * train.wheel_diameter_m) / train.gear_ratio;
}

double running_resistance_n(const TrainSpec& train, double speed_mps) {
  if (speed_mps <= 0.0) return 0.0;
  return train.davis_a_n + speed_mps * (train.davis_b_n_per_mps + speed_mps * train.davis_c_n_per_mps2);
}

}  // namespace lptn::plant
