// A fleet the generator writes, and the request that calibrates it: the workflow suites' fleet tests
// differ in the fleet (FleetOptions), not in how it becomes a request.
#pragma once

#include <filesystem>
#include <vector>

#include "simulator/generate/generate.hpp"
#include "trainer/workflow/calibrate.hpp"

namespace lptn::workflow {

struct GeneratedFleet {
  std::vector<gen::FleetMotorSummary> truth;  // each motor as generated (its id, whether weak)
  calibrate::CalibrationRequest request;                 // the fleet's folder with the motor file written beside it
};

inline GeneratedFleet generate_fleet_request(const gen::FleetOptions& options, const std::filesystem::path& dir) {
  GeneratedFleet g;
  g.truth = gen::generate_fleet(options, dir);
  g.request.fleet = dir.string();
  g.request.motor = (dir / "motor.toml").string();
  return g;
}

}  // namespace lptn::workflow
