// The plants lptn check is tried on: one motor type from the fleet generator, so that a healthy
// motor and one with a clogged filter (30 % weaker cooling, the generator's --weak-motors) drive
// cycles of the same names, and another seed is the same motor a month later.
#pragma once

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "lptn_testing/run_lptn.hpp"

namespace lptn::testing {

struct TwoMotors {
  std::filesystem::path healthy, weak;  // FLEET/<motor_id>
};

// Two motors of one type, cooling exactly as the type's (no scatter) but for the weak one.
inline TwoMotors two_motors(const std::filesystem::path& dir, int seed, int cycles = 4) {
  const Result g = run("generate --fleet --motors 2 --weak-motors 1 --cooling-scatter 0 --cycles " +
                           std::to_string(cycles) + " --seed " + std::to_string(seed) +
                           " --minutes-min 30 --minutes-max 40 --force --out " + dir.string(),
                       dir.parent_path());
  if (g.code != 0) throw std::runtime_error("generate: " + g.err);
  const auto truth = nlohmann::json::parse(std::ifstream(dir / "truth.json"));
  TwoMotors m;
  for (const auto& [id, motor] : truth["motors"].items()) (motor["weak"].get<bool>() ? m.weak : m.healthy) = dir / id;
  return m;
}

}  // namespace lptn::testing
