#pragma once
// The train as one motor sees it: its share of the mass and running resistance, and the gear and
// wheel that turn the motor's torque and speed into force and train speed.

#include "simulator/plant/motor_spec.hpp"

namespace lptn::plant {

struct TrainSpec {
  double mass_per_motor_kg = 26000.0;  // static mass carried per motor (gravity on gradients)
  double rotating_mass_factor = 1.08;  // inertia allowance for wheelsets, gears, rotors
  // Davis running resistance per motor: A + B v + C v^2 (v in m/s, result in N).
  double davis_a_n = 600.0;
  double davis_b_n_per_mps = 10.0;
  double davis_c_n_per_mps2 = 1.5;
  double wheel_diameter_m = 0.92;
  double gear_ratio = 4.3;               // motor turns per wheel turn
  double service_brake_mps2 = 0.9;       // comfortable braking the driver aims for
  double electric_brake_min_kmh = 5.0;   // below this the mechanical brake takes over
};

// Gear ratio that puts the motor's top speed (max_speed_factor x base) at top_speed_kmh.
double gear_ratio_for_top_speed(const MotorSpec& motor, double wheel_diameter_m, double top_speed_kmh);

// Defaults above with the gear ratio matched to the motor (top speed 165 km/h).
TrainSpec default_train_spec(const MotorSpec& motor, double top_speed_kmh = 165.0);

// Effective (accelerated) mass per motor.
double effective_mass_kg(const TrainSpec& train);

double motor_rpm_from_speed(const TrainSpec& train, double speed_mps);
double speed_mps_from_motor_rpm(const TrainSpec& train, double motor_rpm);

// Wheel-rim force per motor from motor torque and back (lossless gear).
double force_from_torque_n(const TrainSpec& train, double torque_nm);
double torque_from_force_nm(const TrainSpec& train, double force_n);

// Running resistance for a speed >= 0 (0 at standstill: the brakes hold the train).
double running_resistance_n(const TrainSpec& train, double speed_mps);

}  // namespace lptn::plant
