// Generated data for the diagnose tests: a fleet dump (fleet_dump.hpp) with chosen hidden effects
// and plant physics, the last two cycles held out, the paper's model calibrated on the rest (LM).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "lptn_testing/fleet_dump.hpp"
#include "trainer/lm/lm.hpp"

namespace lptn::testing {

struct Generated : Dump {
  lm::LmReport calibrated;  // the paper's model (the motor file's), on split.train
};

// `cycles` cycles of `minutes_min`..`minutes_max`; the generator rotates blower modes
// (load following, stepped, fixed 0.5, fixed 1.0), so four or more cycles have every mode.
// `truth` sets true values the built-in truth lacks (an effect of one's own); `plant` adds physics
// the model cannot express (simulator/generate/plant_physics.hpp).
// Any dump the generator can write (`options`), calibrated as below.
inline std::unique_ptr<Generated> generate(const gen::GenerateOptions& options) {
  auto g = std::make_unique<Generated>();
  write_and_load(*g, options);
  const std::size_t n = g->dataset.cycles.size();
  g->split = calibrate::split_cycles(g->dataset, {g->dataset.cycles[n - 2].name, g->dataset.cycles[n - 1].name}, 0, 0);
  g->calibrated = lm::fit_lm(g->motor, g->motor.initial_values(), g->dataset, g->split.train, lm::LmSettings{});
  return g;
}

inline std::unique_ptr<Generated> generate(const std::vector<std::string>& hidden, int cycles, double minutes_min,
                                           double minutes_max, std::uint64_t seed,
                                           const std::vector<std::pair<std::string, double>>& truth = {},
                                           gen::PlantPhysicsSet plant = 0) {
  gen::GenerateOptions o;
  o.cycles = cycles;
  o.seed = seed;
  o.min_duration_s = minutes_min * 60;
  o.max_duration_s = minutes_max * 60;
  o.truth_overrides = truth;
  o.plant = plant;
  for (const std::string& e : hidden) o.hidden |= effect_bit(effect_index(e));
  return generate(o);
}

}  // namespace lptn::testing
