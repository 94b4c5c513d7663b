// Generated data for the diagnose tests: a fleet dump with chosen hidden effects, the paper's
// model calibrated on it (LM), the last two cycles held out.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "lptn_testing/temp_dir.hpp"
#include "tools/generate/generate.hpp"
#include "trainer/calibrate/lm.hpp"
#include "trainer/diagnose/diagnose.hpp"

namespace lptn::testing {

struct Generated {
  TempDir dir;
  data::Dataset dataset;
  MotorFile motor;
  Split split;
  LmReport calibrated;  // the paper's model (the motor file's), on split.train
};

// `cycles` cycles of `minutes_min`..`minutes_max`; the generator rotates blower modes
// (load following, stepped, fixed 0.5, fixed 1.0), so four or more cycles have every mode.
// `truth` sets true values the built-in truth lacks (an effect of one's own); `plant` adds physics
// the model cannot express (tools/generate/plant_physics.hpp).
// Any dump the generator can write (`options`), calibrated as below.
inline std::unique_ptr<Generated> generate(const gen::GenerateOptions& options) {
  auto g = std::make_unique<Generated>();
  gen::generate(options, g->dir.path());
  g->dataset = data::load_fleet_dump({g->dir.path()});
  g->motor = load_motor_file(g->dir.path() / "motor.toml");
  const std::size_t n = g->dataset.cycles.size();
  g->split = split_cycles(g->dataset, {g->dataset.cycles[n - 2].name, g->dataset.cycles[n - 1].name}, 0, 0);
  g->calibrated = fit_lm(g->motor, g->motor.initial_values(), g->dataset, g->split.train, LmSettings{});
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
