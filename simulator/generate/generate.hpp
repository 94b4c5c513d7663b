// `lptn generate`: a fleet dump with a known truth, from the synthetic plant.
//
// Each cycle: a driving cycle from train dynamics (simulator/plant), the motor's operating point at
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
#include "simulator/generate/plant_physics.hpp"
#include "trainer/data/sensor_fault.hpp"

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
  // This motor's factor on every conductance to air (cooling_factor.hpp): a fleet's scatter.
  double cooling_factor = 1;
  // Sensors that read wrong while the motor is fine (trainer/data/sensor_fault.hpp), `first` the
  // 0-based cycle: the readings carry the fault, truth/ the true temperatures.
  std::vector<data::SensorFault> sensor_faults;
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
  double cooling_factor = 1;  // on every conductance to air (the motor's, times cooling_fouling's)
};

// Writes DIR/<cycle>.csv (the data contract), DIR/motor.toml (what the user knows: the paper's
// model with initial guesses), DIR/truth.json (true parameters, hidden effects, sensor model,
// per-cycle summaries) and DIR/truth/<cycle>.csv (true node temperatures at the logging step).
// `progress(i, n, summary)` is called after each cycle. Deterministic for a given seed.
std::vector<CycleSummary> generate(const GenerateOptions& options, const std::filesystem::path& dir,
                                   const std::function<void(int, int, const CycleSummary&)>& progress = {});

// A fleet of one motor type: motors that differ in their cooling (a few per cent of scatter),
// some of them with a clogged filter or a weak blower.
struct FleetOptions {
  int motors = 6;
  int weak_motors = 1;           // drawn at random (by the seed) among the motors
  double cooling_scatter = 0.03;  // standard deviation of the healthy motors' log cooling factor
  double weak_factor = 0.7;       // a weak motor's cooling factor (30 % below nominal)
  GenerateOptions motor;          // each motor's cycles; the seed is the fleet's
};

struct FleetMotorSummary {
  std::string id;  // "motor_01", ...: its subdirectory
  double cooling_factor = 1;
  bool weak = false;
  std::vector<CycleSummary> cycles;
};

// Writes DIR/motor.toml (the motor type), DIR/truth.json (each motor's true cooling factor and
// whether it is weak) and DIR/<id>/ for every motor as generate() writes a dump. `progress(i, n,
// motor)` after each motor. Deterministic for a given seed.
std::vector<FleetMotorSummary> generate_fleet(const FleetOptions& options, const std::filesystem::path& dir,
                                              const std::function<void(int, int, const FleetMotorSummary&)>& progress = {});

}  // namespace lptn::gen
