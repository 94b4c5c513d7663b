#include "simulator/generate/generate.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "simulator/generate/plant_truth.hpp"
#include "trainer/model/cooling_factor.hpp"
#include "simulator/plant/blower.hpp"
#include "simulator/plant/cycle_kind.hpp"
#include "simulator/plant/driving_cycle.hpp"
#include "simulator/plant/operating_point.hpp"
#include "simulator/plant/random.hpp"
#include "simulator/plant/train_spec.hpp"

namespace lptn::gen {
namespace {

constexpr double kLogStepS = 0.1;
constexpr int kTruthSubsteps = 4;  // the truth is integrated finer than the model will be

// Appends a number with a fixed number of decimals (no locale, no allocation per cell).
void put(std::string& line, double v, int decimals) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  line.append(buf, r.ptr);
}

double quantize(double v, double step) { return std::round(v / step) * step; }

// What `sensor` reads in cycle `i` of `n` where the temperature at it is `t_c`, before its noise.
double faulty(const std::vector<data::SensorFault>& faults, data::Channel sensor, double t_c, int i, int n) {
  for (const data::SensorFault& f : faults)
    if (f.sensor == sensor) t_c = f.reading(t_c, static_cast<std::size_t>(i), static_cast<std::size_t>(n));
  return t_c;
}

struct CyclePlan {
  plant::CycleKind kind;
  plant::BlowerPolicy blower;
  std::string blower_name;
};

// Kinds rotate through the five; blower modes rotate through four with another period, so that
// every kind meets airflow that follows the load and airflow that does not (fixed and stepped
// levels) — data on which airflow effects can be told from load effects.
CyclePlan plan_cycle(int i) {
  CyclePlan p;
  p.kind = plant::kAllCycleKinds[i % std::size(plant::kAllCycleKinds)];
  switch (i % 4) {
    case 0: p.blower.mode = plant::BlowerMode::load_following; p.blower_name = "load_following"; break;
    case 1: p.blower.mode = plant::BlowerMode::stepped; p.blower_name = "stepped"; break;
    case 2: p.blower.mode = plant::BlowerMode::fixed; p.blower.fixed_level = 0.5; p.blower_name = "fixed_0.5"; break;
    default: p.blower.mode = plant::BlowerMode::fixed; p.blower.fixed_level = 1.0; p.blower_name = "fixed_1.0"; break;
  }
  return p;
}

struct Span {
  double start_s, end_s;
  bool contains(double t) const { return t >= start_s && t < end_s; }
};

bool in_any(const std::vector<Span>& spans, double t) {
  for (const Span& s : spans)
    if (s.contains(t)) return true;
  return false;
}

// Short dropouts a real logger has: whole rows lost for a second now and then, the stator
// sensor's value missing for a few seconds. All within the loader's bridging limits.
std::vector<Span> dropouts(plant::Rng& rng, double duration_s, double every_s, double length_s) {
  std::vector<Span> out;
  for (double t = rng.uniform(0.3, 1.0) * every_s; t + length_s < duration_s - 60; t += rng.uniform(0.5, 1.5) * every_s)
    out.push_back({t, t + length_s});
  return out;
}

void write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

}  // namespace

std::vector<CycleSummary> generate(const GenerateOptions& options, const std::filesystem::path& dir,
                                   const std::function<void(int, int, const CycleSummary&)>& progress) {
  if (options.cycles < 1) throw std::invalid_argument("--cycles must be at least 1");
  std::filesystem::create_directories(dir / "truth");
  const model::MotorFile motor = example_motor_file();
  ParamVector<double> truth = true_parameters();
  for (const auto& [name, value] : options.truth_overrides) {
    const int p = param_index(name);
    if (p < 0) throw std::invalid_argument("--truth: unknown parameter '" + name + "'");
    truth[p] = value;
  }
  const Model<double> plant_model(motor.constants, options.hidden);
  const plant::MotorSpec spec = plant_motor_spec(motor.constants);
  const plant::TrainSpec train = plant::default_train_spec(spec);

  std::vector<CycleSummary> summaries;
  for (int i = 0; i < options.cycles; ++i) {
    const CyclePlan plan = plan_cycle(i);
    const std::uint64_t seed = plant::derive_seed(options.seed, static_cast<std::uint64_t>(i));
    plant::Rng rng(plant::derive_seed(seed, 1000));
    const double duration = rng.uniform(options.min_duration_s, options.max_duration_s);
    const std::vector<plant::DriveSample> drive =
        plant::drive_cycle(plan.kind, spec, train, plan.blower, duration, kLogStepS, seed);

    CycleSummary summary;
    char name[64];
    std::snprintf(name, sizeof name, "cycle_%02d_%s", i + 1, std::string(plant::to_string(plan.kind)).c_str());
    summary.name = name;
    summary.kind = plant::to_string(plan.kind);
    summary.blower = plan.blower_name;
    summary.duration_s = drive.empty() ? 0.0 : drive.back().t_s - drive.front().t_s;
    summary.min_ambient_c = 1e9;
    summary.max_ambient_c = -1e9;

    // The motor has stood before the cycle: soaked through at a few kelvin above ambient.
    double x[kMaxStates];
    const double soak = drive.front().ambient_c + rng.uniform(0.0, 25.0);
    plant_model.initial_state(x, soak, soak);
    PlantExtraState extra = initial_extra_state(soak);
    const ParamVector<double> cycle_truth =
        model::with_cooling_factor(cycle_parameters(options.plant, truth, i, options.cycles), options.cooling_factor);
    summary.cooling_factor = options.cooling_factor * cooling_factor(options.plant, i, options.cycles);

    const std::vector<Span> lost_rows = dropouts(rng, duration, 1200.0, 1.0);
    const std::vector<Span> lost_stator = dropouts(rng, duration, 1800.0, 5.0);
    std::vector<Span> long_stator, long_speed;
    if (options.long_gaps) {
      long_stator.push_back({0.4 * duration, 0.4 * duration + 40.0});
      long_speed.push_back({0.7 * duration, 0.7 * duration + 5.0});
    }

    std::string csv = options.rotor_sensor
                          ? "time_s,speed_rpm,torque_nm,current_a,frequency_hz,voltage_v,airflow_m3s,ambient_c,stator_winding_c,rotor_c\n"
                          : "time_s,speed_rpm,torque_nm,current_a,frequency_hz,voltage_v,airflow_m3s,ambient_c,stator_winding_c\n";
    std::string truth_csv = "time_s,stator_winding_c,stator_core_c,rotor_winding_c,rotor_core_c,stator_sensor_c\n";
    csv.reserve(drive.size() * 90);
    truth_csv.reserve(drive.size() * 50);
    const SensorModel& sensors = options.sensors;
    for (std::size_t k = 0; k < drive.size(); ++k) {
      const plant::DriveSample& s = drive[k];
      const plant::OperatingPoint op =
          plant::operating_point(spec, s.speed_rpm, s.torque_nm, x[kRotorWinding], x[kStatorWinding]);
      Inputs<double> in;
      in.speed_rpm = s.speed_rpm;
      in.torque_nm = op.pulses_on ? s.torque_nm : 0.0;
      in.current_a = op.current_a;
      in.frequency_hz = op.frequency_hz;
      in.voltage_v = op.voltage_v;
      in.airflow_m3s = s.airflow_m3s;
      in.ambient_c = s.ambient_c;
      in.has_torque = true;
      in.has_voltage = true;

      // The truth at this instant, then what the logger recorded of it.
      const double t = s.t_s;
      put(truth_csv, t, 1);
      for (int node = 0; node < kNumNodes; ++node) {
        truth_csv += ',';
        put(truth_csv, x[node], 3);
      }
      truth_csv += ',';
      put(truth_csv, plant_model.stator_sensor(x), 3);
      truth_csv += '\n';
      summary.max_stator_winding_c = std::max(summary.max_stator_winding_c, x[kStatorWinding]);
      summary.max_rotor_c = std::max(summary.max_rotor_c, x[kRotorWinding]);
      summary.min_ambient_c = std::min(summary.min_ambient_c, s.ambient_c);
      summary.max_ambient_c = std::max(summary.max_ambient_c, s.ambient_c);

      const double stamp = t + rng.uniform(-0.004, 0.004);
      if (!in_any(lost_rows, t)) {
        put(csv, stamp, 3);
        csv += ',';
        if (!in_any(long_speed, t)) put(csv, in.speed_rpm + 1.0 * rng.normal(), 1);
        csv += ',';
        put(csv, in.torque_nm + 5.0 * rng.normal(), 1);
        csv += ',';
        put(csv, std::max(0.0, in.current_a + 0.5 * rng.normal()), 2);
        csv += ',';
        put(csv, in.frequency_hz + 0.02 * rng.normal(), 3);
        csv += ',';
        put(csv, std::max(0.0, in.voltage_v + 3.0 * rng.normal()), 1);
        csv += ',';
        if (k % 10 == 0) put(csv, std::max(0.0, in.airflow_m3s + 0.01 * rng.normal()), 3);
        csv += ',';
        if (k % 50 == 0) put(csv, quantize(in.ambient_c + 0.1 * rng.normal(), 0.1), 1);
        csv += ',';
        if (k % 10 == 0 && !in_any(lost_stator, t) && !in_any(long_stator, t)) {
          const double reading =
              faulty(options.sensor_faults, data::Channel::stator_winding_c, plant_model.stator_sensor(x), i, options.cycles) +
              sensors.stator_noise_k * rng.normal();
          put(csv, quantize(reading, sensors.temperature_resolution_k), 1);
        }
        if (options.rotor_sensor) {
          csv += ',';
          if (k % 10 == 5) {
            const double reading =
                faulty(options.sensor_faults, data::Channel::rotor_c, plant_model.rotor_sensor(x), i, options.cycles) +
                sensors.rotor_noise_k * rng.normal();
            put(csv, quantize(reading, sensors.temperature_resolution_k), 1);
          }
        }
        csv += '\n';
      }
      for (int sub = 0; sub < kTruthSubsteps; ++sub) {
        // What the motor really breathes and carries; the log above keeps what the logger saw.
        const Inputs<double> truth_in = plant_inputs(options.plant, motor.constants, in, x, cycle_truth);
        plant_model.step(x, truth_in, cycle_truth.data(), kLogStepS / kTruthSubsteps);
        step_plant_physics(options.plant, motor.constants, truth_in, x, extra, kLogStepS / kTruthSubsteps);
      }
    }
    write_file(dir / (summary.name + ".csv"), csv);
    write_file(dir / "truth" / (summary.name + ".csv"), truth_csv);
    summaries.push_back(summary);
    if (progress) progress(i + 1, options.cycles, summary);
  }

  write_file(dir / "motor.toml", model::format_motor_file(motor));
  nlohmann::json j;
  j["seed"] = options.seed;
  j["hidden_effects"] = nlohmann::json::array();
  for (int e = 0; e < kNumEffects; ++e)
    if (options.hidden & effect_bit(e)) j["hidden_effects"].push_back(std::string(EffectLibrary::kNames[e]));
  j["plant_physics"] = plant_physics_names(options.plant);
  j["sensor_faults"] = nlohmann::json::array();
  for (const data::SensorFault& f : options.sensor_faults) {
    const std::string first = f.first < summaries.size() ? summaries[f.first].name : "";
    j["sensor_faults"].push_back({{"sensor", data::sensor_name(f.sensor)}, {"shape", data::to_string(f.shape)},
                                  {"size", f.size}, {"first_cycle", first}, {"spec", data::format_sensor_fault(f, first)}});
  }
  for (int p = 0; p < kNumParams; ++p) {
    const int e = effect_of_param(p);
    if (e >= 0 && !(options.hidden & effect_bit(e))) continue;
    j["parameters"][std::string(param_spec(p).name)] = {{"value", truth[p]}, {"unit", std::string(param_spec(p).unit)}};
  }
  j["sensors"] = {{"stator_noise_k", options.sensors.stator_noise_k},
                  {"rotor_noise_k", options.sensors.rotor_noise_k},
                  {"temperature_resolution_k", options.sensors.temperature_resolution_k}};
  for (const CycleSummary& s : summaries) {
    j["cycles"].push_back({{"name", s.name}, {"kind", s.kind}, {"blower", s.blower}, {"duration_s", s.duration_s},
                           {"max_stator_winding_c", s.max_stator_winding_c}, {"max_rotor_c", s.max_rotor_c},
                           {"min_ambient_c", s.min_ambient_c}, {"max_ambient_c", s.max_ambient_c},
                           {"cooling_factor", s.cooling_factor}});
  }
  j["cooling_factor"] = options.cooling_factor;
  write_file(dir / "truth.json", j.dump(2) + "\n");
  return summaries;
}

std::vector<FleetMotorSummary> generate_fleet(const FleetOptions& options, const std::filesystem::path& dir,
                                              const std::function<void(int, int, const FleetMotorSummary&)>& progress) {
  if (options.motors < 1) throw std::invalid_argument("--motors must be at least 1");
  if (options.weak_motors < 0 || options.weak_motors > options.motors)
    throw std::invalid_argument("--weak-motors must be between 0 and --motors");
  std::filesystem::create_directories(dir);
  plant::Rng rng(plant::derive_seed(options.motor.seed, 7000));
  // Which motors are weak: a seeded draw without replacement.
  std::vector<int> order(static_cast<std::size_t>(options.motors));
  for (int m = 0; m < options.motors; ++m) order[static_cast<std::size_t>(m)] = m;
  for (int m = options.motors - 1; m > 0; --m)
    std::swap(order[static_cast<std::size_t>(m)],
              order[static_cast<std::size_t>(std::min(m, static_cast<int>(rng.uniform(0.0, m + 1.0))))]);
  std::vector<bool> weak(static_cast<std::size_t>(options.motors), false);
  for (int w = 0; w < options.weak_motors; ++w) weak[static_cast<std::size_t>(order[static_cast<std::size_t>(w)])] = true;

  std::vector<FleetMotorSummary> out;
  nlohmann::json j;
  j["seed"] = options.motor.seed;
  j["cooling_scatter"] = options.cooling_scatter;
  j["weak_factor"] = options.weak_factor;
  for (int m = 0; m < options.motors; ++m) {
    FleetMotorSummary s;
    char id[32];
    std::snprintf(id, sizeof id, "motor_%02d", m + 1);
    s.id = id;
    s.weak = weak[static_cast<std::size_t>(m)];
    const double scatter = std::exp(options.cooling_scatter * rng.normal());  // drawn for every motor alike
    s.cooling_factor = s.weak ? options.weak_factor : scatter;
    GenerateOptions motor = options.motor;
    motor.seed = plant::derive_seed(options.motor.seed, 7001 + static_cast<std::uint64_t>(m));
    motor.cooling_factor = s.cooling_factor;
    s.cycles = generate(motor, dir / s.id);
    j["motors"][s.id] = {{"cooling_factor", s.cooling_factor}, {"weak", s.weak}};
    out.push_back(s);
    if (progress) progress(m + 1, options.motors, out.back());
  }
  write_file(dir / "motor.toml", model::format_motor_file(example_motor_file()));
  write_file(dir / "truth.json", j.dump(2) + "\n");
  return out;
}

}  // namespace lptn::gen
