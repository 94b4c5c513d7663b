// `lptn generate`: a fleet dump with a known truth, from the synthetic plant.
//
// Each cycle: a driving cycle from train dynamics (tools/plant), the motor's operating point at
// every step from speed, torque and the TRUE rotor temperature (slip grows as the cage warms),
// the thermal truth from the project's own model with the true parameters and any hidden effects
// (integrated at a quarter of the logging step), then measurement: noise, quantization, channels
// at their own rates, jittered time stamps and short dropouts.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "lptn/model.hpp"
#include "tools/generate/plant_physics.hpp"

namespace lptn::gen {

struct SensorModel {
  double stator_noise_k = 0.4;  // standard deviation of the stator winding sensor
  double rotor_noise_k = 0.5;
  double temperature_resolution_k = 0.1;
};

struct GenerateOptions {
  int cycles = 9;
  std::uint64_t seed = 1;
  EffectSet hidden = 0;
  PlantPhysicsSet plant = 0;  // physics beyond the model (plant_physics.hpp)
  double min_duration_s = 3600;
  double max_duration_s = 5400;
  bool rotor_sensor = true;  // bench-style rotor telemetry (fleet data often lacks it)
  bool long_gaps = false;    // add gaps the loader must mask or split at
  SensorModel sensors;
  // True values by parameter name, over the built-in truth (plant_truth.hpp): for an effect of
  // one's own, whose parameters the built-in truth leaves at their initial values.
  std::vector<std::pair<std::string, double>> truth_overrides;
};

struct CycleSummary {
  std::string name;
  std::string kind;
  std::string blower;
  double duration_s = 0;
  double max_stator_winding_c = 0;
  double max_rotor_c = 0;
  double min_ambient_c = 0;
  double max_ambient_c = 0;
  double cooling_factor = 1;  // on every conductance to air (cooling_fouling)
};

// Writes DIR/<cycle>.csv (the data contract), DIR/motor.toml (what the user knows: the paper's
// model with initial guesses), DIR/truth.json (true parameters, hidden effects, sensor model,
// per-cycle summaries) and DIR/truth/<cycle>.csv (true node temperatures at the logging step).
// `progress(i, n, summary)` is called after each cycle. Deterministic for a given seed.
std::vector<CycleSummary> generate(const GenerateOptions& options, const std::filesystem::path& dir,
                                   const std::function<void(int, int, const CycleSummary&)>& progress = {});

}  // namespace lptn::gen
