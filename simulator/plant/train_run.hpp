#pragma once
// The driver and the train's longitudinal dynamics: station to station, Newton's law per motor
// through gear and wheel, torque always inside the motor's envelope.

#include <cstdint>

#include "simulator/plant/cycle_kind.hpp"
#include "simulator/plant/gradient_profile.hpp"
#include "simulator/plant/motor_spec.hpp"
#include "simulator/plant/random.hpp"
#include "simulator/plant/route_profile.hpp"
#include "simulator/plant/segment.hpp"
#include "simulator/plant/train_spec.hpp"

namespace lptn::plant {

class TrainRun {
 public:
  TrainRun(CycleKind kind, const MotorSpec& motor, const TrainSpec& train, std::uint64_t seed);

  struct Command {
    double speed_rpm;  // motor speed at the start of the step (signed by direction)
    double torque_nm;  // electric torque held over the step (signed: positive drives forward)
    bool moving;
  };

  // Decides the torque for the next h_s seconds at the present state, then moves the train.
  Command step(double h_s);

 private:
  void start_segment();
  double desired_force_n(double v, double balance_n, double max_traction_n);

  MotorSpec motor_;
  TrainSpec train_;
  RouteProfile route_;
  Rng rng_;
  GradientProfile gradient_;
  OuNoise force_noise_;   // the driver's hand on the controller while holding speed
  OuNoise speed_wobble_;  // ... and the speed he settles at
  Segment segment_{};
  int direction_ = 1;
  double dwell_left_s_ = 0.0;
  double position_m_ = 0.0;        // within the segment
  double track_position_m_ = 0.0;  // distance travelled since the start (gradient lookup)
  double speed_mps_ = 0.0;         // >= 0, along direction_
  double demand_n_ = 0.0;          // jerk-limited wheel-force demand per motor
  bool braking_to_stop_ = false;
};

}  // namespace lptn::plant
