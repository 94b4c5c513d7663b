// lptn generate: a fleet dump with a known truth from the synthetic plant.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "hostio/atomic_file.hpp"
#include "programs/cli/commands.hpp"
#include "simulator/generate/generate.hpp"

namespace lptn::cli {
namespace {

EffectSet parse_effects(const std::string& list) {
  EffectSet set = 0;
  std::stringstream in(list);
  std::string name;
  while (std::getline(in, name, ',')) {
    if (name.empty()) continue;
    const int e = effect_index(name);
    if (e < 0) {
      std::string known;
      for (auto k : EffectLibrary::kNames) known += (known.empty() ? "" : ", ") + std::string(k);
      throw hostio::BadInput("--hidden: unknown effect '" + name + "' (known: " + known + ")");
    }
    set |= effect_bit(e);
  }
  return set;
}

gen::PlantPhysicsSet parse_plant(const std::string& list) {
  gen::PlantPhysicsSet set = 0;
  std::stringstream in(list);
  std::string name;
  while (std::getline(in, name, ',')) {
    if (name.empty()) continue;
    const gen::PlantPhysics p = gen::plant_physics_index(name);
    if (p == gen::PlantPhysics::count) {
      std::string known;
      for (auto k : gen::kPlantPhysicsNames) known += (known.empty() ? "" : ", ") + std::string(k);
      throw hostio::BadInput("--plant: unknown plant physics '" + name + "' (known: " + known + ")");
    }
    set |= gen::plant_bit(p);
  }
  return set;
}

// NAME=VALUE pairs: true values of parameters the built-in truth does not set (an effect of one's own).
std::vector<std::pair<std::string, double>> parse_truth(const std::vector<std::string>& items) {
  std::vector<std::pair<std::string, double>> out;
  for (const std::string& item : items) {
    const std::size_t eq = item.find('=');
    const std::string name = item.substr(0, eq);
    if (eq == std::string::npos || param_index(name) < 0)
      throw hostio::BadInput("--truth: expected PARAMETER=VALUE with a known parameter, got '" + item + "'");
    const std::string text = item.substr(eq + 1);
    std::size_t used = 0;
    double value = 0;
    try {
      value = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != text.size() || !std::isfinite(value))
      throw hostio::BadInput("--truth: '" + item + "': the value is not a number");
    out.emplace_back(name, value);
  }
  return out;
}

// SENSOR:SHAPE:SIZE:FIRST with FIRST a 1-based cycle number within --cycles.
std::vector<data::SensorFault> parse_sensor_faults(const std::vector<std::string>& items, int cycles) {
  std::vector<data::SensorFault> out;
  for (const std::string& item : items) {
    data::SensorFaultSpec spec;
    try {
      spec = data::parse_sensor_fault(item);
    } catch (const hostio::BadInput& e) {
      throw hostio::BadInput(std::string("--sensor-fault: ") + e.what());
    }
    int first = 0;
    const auto [ptr, ec] = std::from_chars(spec.first_cycle.data(), spec.first_cycle.data() + spec.first_cycle.size(), first);
    if (ec != std::errc() || ptr != spec.first_cycle.data() + spec.first_cycle.size() || first < 1 || first > cycles)
      throw hostio::BadInput("--sensor-fault: '" + item + "': FIRST must be a cycle number from 1 to " + std::to_string(cycles));
    spec.fault.first = static_cast<std::size_t>(first - 1);
    out.push_back(spec.fault);
  }
  return out;
}

}  // namespace

void add_generate(CLI::App& app) {
  auto* cmd = app.add_subcommand("generate", "Generate a fleet dump with a known truth from the synthetic plant");
  struct Args {
    std::string out, hidden, plant;
    std::vector<std::string> truth, sensor_faults;
    gen::GenerateOptions options;
    double minutes_min = 60, minutes_max = 90;
    bool no_rotor = false, force = false, fleet = false;
    gen::FleetOptions fleet_options;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("--out", args->out, "Output directory (cycle CSVs, motor.toml, truth.json, truth/)")->required();
  auto* cycles = cmd->add_option("--cycles", args->options.cycles, "Number of driving cycles (with --fleet: per motor, default 3)")
                     ->capture_default_str()->check(CLI::Range(1, 10000));
  auto* fleet = cmd->add_flag("--fleet", args->fleet,
                              "A fleet of one motor type: OUT/<motor_id>/ per motor, each with its own cooling factor");
  cmd->add_option("--motors", args->fleet_options.motors, "--fleet: number of motors")
      ->capture_default_str()->check(CLI::Range(1, 1000))->needs(fleet);
  cmd->add_option("--weak-motors", args->fleet_options.weak_motors,
                  "--fleet: motors whose cooling is 30 % below nominal (a clogged filter), drawn by the seed")
      ->capture_default_str()->check(CLI::Range(0, 1000))->needs(fleet);
  cmd->add_option("--cooling-scatter", args->fleet_options.cooling_scatter,
                  "--fleet: standard deviation of the healthy motors' log cooling factor")
      ->capture_default_str()->check(CLI::Range(0.0, 0.5))->needs(fleet);
  cmd->add_option("--seed", args->options.seed, "Random seed: the same seed gives the same data")->capture_default_str();
  cmd->add_option("--hidden", args->hidden, "Effects the plant has and the paper's model lacks, comma-separated");
  std::string plant_names;
  for (auto k : gen::kPlantPhysicsNames) plant_names += (plant_names.empty() ? "" : ", ") + std::string(k);
  cmd->add_option("--plant", args->plant,
                  "Physics the model cannot express (" + plant_names +
                      "), comma-separated: to test what diagnose says about a real motor");
  cmd->add_option("--truth", args->truth, "True value of a parameter, NAME=VALUE (repeatable; for effects of your own)");
  cmd->add_option("--sensor-fault", args->sensor_faults,
                  "A sensor that reads wrong while the motor is fine, SENSOR:SHAPE:SIZE:FIRST: stator or rotor; offset (K), "
                  "gain (relative: 0.03 reads 3 % high in degC) or drift (K in the last cycle, growing linearly from "
                  "cycle FIRST); FIRST the 1-based first faulty cycle (repeatable)");
  cmd->add_option("--minutes-min", args->minutes_min, "Shortest cycle, minutes")->capture_default_str()->check(CLI::Range(2.0, 1440.0));
  cmd->add_option("--minutes-max", args->minutes_max, "Longest cycle, minutes")->capture_default_str()->check(CLI::Range(2.0, 1440.0));
  cmd->add_option("--stator-noise", args->options.sensors.stator_noise_k, "Stator sensor noise, K (standard deviation)")
      ->capture_default_str()->check(CLI::Range(0.0, 10.0));
  cmd->add_flag("--no-rotor", args->no_rotor, "Leave out the rotor temperature (as most fleet data does)");
  cmd->add_flag("--long-gaps", args->options.long_gaps, "Add gaps too long to bridge (to exercise the loader)");
  cmd->add_flag("--force", args->force, "Replace the output directory if it exists");
  cmd->callback([args, cycles] {
    if (args->minutes_max < args->minutes_min) throw hostio::BadInput("--minutes-max must not be below --minutes-min");
    check_output_path(args->out, args->force);
    args->options.hidden = parse_effects(args->hidden);
    args->options.plant = parse_plant(args->plant);
    args->options.truth_overrides = parse_truth(args->truth);
    args->options.sensor_faults = parse_sensor_faults(args->sensor_faults, args->options.cycles);
    if (args->no_rotor)
      for (const data::SensorFault& f : args->options.sensor_faults)
        if (f.sensor == data::Channel::rotor_c) throw hostio::BadInput("--sensor-fault: a rotor fault with --no-rotor (no rotor readings)");
    args->options.min_duration_s = 60 * args->minutes_min;
    args->options.max_duration_s = 60 * args->minutes_max;
    args->options.rotor_sensor = !args->no_rotor;
    if (args->fleet) {
      if (args->fleet_options.weak_motors > args->fleet_options.motors)
        throw hostio::BadInput("--weak-motors must not exceed --motors");
      if (cycles->count() == 0) args->options.cycles = 3;
      args->fleet_options.motor = args->options;
      hostio::AtomicDirectory out(args->out, args->force);
      double hours = 0;
      gen::generate_fleet(args->fleet_options, out.path(), [&](int i, int n, const gen::FleetMotorSummary& m) {
        for (const gen::CycleSummary& c : m.cycles) hours += c.duration_s / 3600;
        // Which motor is weak is the truth the calibration is to find: truth.json says it, not this line.
        std::fprintf(stderr, "[%d/%d] %s: %zu cycles\n", i, n, m.id.c_str(), m.cycles.size());
      });
      out.commit();
      std::printf("wrote a fleet of %d motors, %d cycles each (%.1f h of 10 Hz data), to %s (motor.toml, truth.json)\n",
                  args->fleet_options.motors, args->options.cycles, hours, args->out.c_str());
      return;
    }
    hostio::AtomicDirectory out(args->out, args->force);
    double hours = 0;
    gen::generate(args->options, out.path(), [&](int i, int n, const gen::CycleSummary& s) {
      hours += s.duration_s / 3600;
      std::fprintf(stderr, "[%d/%d] %-22s %-10s blower %-14s %5.1f min, stator max %5.1f C, rotor max %5.1f C\n", i, n,
                   s.name.c_str(), s.kind.c_str(), s.blower.c_str(), s.duration_s / 60, s.max_stator_winding_c, s.max_rotor_c);
    });
    out.commit();
    std::printf("wrote %d cycles (%.1f h of 10 Hz data) to %s (motor.toml, truth.json, truth/)\n", args->options.cycles,
                hours, args->out.c_str());
  });
}

}  // namespace lptn::cli
