// The two sensors a diagnosis compares the model with: each one's name, its channel in the data
// and its trace in a simulation. One table for the adequacy, the block errors and the coarse
// grid's correction, which each walk both sensors.
#pragma once

#include <vector>

#include "trainer/data/dataset.hpp"
#include "trainer/model/simulate.hpp"

namespace lptn::diagnose::internal {

struct SensorTrace {
  const char* name;
  data::Channel channel;
  std::vector<float> model::CycleSimulation::*trace;
};
inline constexpr SensorTrace kSensorTraces[] = {
    {"stator", data::Channel::stator_winding_c, &model::CycleSimulation::stator_sensor},
    {"rotor", data::Channel::rotor_c, &model::CycleSimulation::rotor_sensor}};

}  // namespace lptn::diagnose::internal
