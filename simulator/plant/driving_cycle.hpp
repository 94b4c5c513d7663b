#pragma once
// Synthetic driving cycles: the mechanical inputs of the plant (motor speed and torque) with the
// cooling air and the ambient temperature, sampled at a fixed step.

#include <cstdint>
#include <vector>

#include "simulator/plant/blower.hpp"
#include "simulator/plant/cycle_kind.hpp"
#include "simulator/plant/motor_spec.hpp"
#include "simulator/plant/train_spec.hpp"

namespace lptn::plant {

struct DriveSample {
  double t_s;
  double speed_rpm;  // motor speed, negative when running in reverse
  double torque_nm;  // electric torque, same sign as speed when motoring, opposite when braking
  double airflow_m3s;
  double ambient_c;
};

// Samples at t = 0, dt, ..., up to and including duration_s (floor(duration/dt) + 1 of them),
// each the instantaneous state at its time. The train runs station to station (internally at
// <= 0.25 s steps) and simply stops being sampled at duration_s; the last samples may be
// standing. Deterministic for a seed on any platform; the driver, blower and ambient draw from
// separate streams, so the same seed with another blower policy gives the same speed and torque.
// Throws std::invalid_argument for dt_s <= 0 or duration_s < 0.
std::vector<DriveSample> drive_cycle(CycleKind kind, const MotorSpec& motor, const TrainSpec& train,
                                     const BlowerPolicy& blower, double duration_s, double dt_s,
                                     std::uint64_t seed);

}  // namespace lptn::plant
