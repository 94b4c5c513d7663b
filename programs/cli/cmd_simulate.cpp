// lptn simulate: run the model over every cycle of a fleet dump and compare it with the sensors.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hostio/atomic_file.hpp"
#include "programs/cli/commands.hpp"
#include "programs/cli/data_map_option.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/model/motor_file.hpp"
#include "trainer/model/motor_plausibility.hpp"
#include "trainer/model/simulate.hpp"

namespace lptn::cli {
namespace {

nlohmann::json metrics_json(const model::ErrorMetrics& m) {
  return {{"rmse_k", m.rmse_k}, {"mean_abs_k", m.mean_abs_k}, {"max_abs_k", m.max_abs_k}, {"bias_k", m.bias_k},
          {"samples", m.samples}};
}

void put(std::string& s, double v, int decimals) {
  if (std::isnan(v)) return;  // missing stays an empty cell, as in the data contract
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  s.append(buf, r.ptr);
}

std::string trace_csv(const data::Cycle& cycle, const model::CycleSimulation& sim) {
  std::string s = "time_s,stator_measured_c,stator_model_c,stator_residual_k,rotor_measured_c,rotor_model_c,"
                  "stator_winding_c,stator_core_c,rotor_winding_c,rotor_core_c\n";
  for (std::size_t k = 0; k < cycle.steps; ++k) {
    const double ms = cycle.at(data::Channel::stator_winding_c, k);
    const double mr = cycle.at(data::Channel::rotor_c, k);
    put(s, cycle.time_s(k), 2);
    s += ',';
    put(s, ms, 2);
    s += ',';
    put(s, sim.stator_sensor[k], 3);
    s += ',';
    put(s, sim.stator_sensor[k] - ms, 3);
    s += ',';
    put(s, mr, 2);
    s += ',';
    put(s, sim.rotor_sensor[k], 3);
    for (int i = 0; i < kNumNodes; ++i) {
      s += ',';
      put(s, sim.nodes[i][k], 3);
    }
    s += '\n';
  }
  return s;
}

}  // namespace

void add_simulate(CLI::App& app) {
  auto* cmd = app.add_subcommand("simulate", "Run the model over a fleet dump and compare it with the measurements");
  struct Args {
    std::vector<std::string> data;
    std::string motor, out, map;
    std::vector<std::string> set;
    bool json = false, force = false;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("--data", args->data, "Directories of cycle CSVs, or CSV files")->required()->expected(1, -1);
  cmd->add_option("--motor", args->motor, "Motor file (constants, parameters, effects)")->required();
  cmd->add_option("--set", args->set, "Override a parameter: NAME=VALUE (repeatable)");
  cmd->add_option("--out", args->out, "Directory for per-cycle traces (CSV) and metrics.json");
  add_map_option(cmd, args->map);
  cmd->add_flag("--json", args->json, "Print the metrics as JSON");
  cmd->add_flag("--force", args->force, "Replace --out if it exists");
  cmd->callback([args] {
    // Inputs first, then the output, then the work: nothing long runs into a bad path.
    for (const std::string& d : args->data) check_input_path(d, "--data");
    check_input_path(args->motor, "--motor", InputPath::file);
    check_output_path(args->out, args->force);
    const model::MotorFile motor = model::load_motor_file(args->motor);
    ParamVector<double> params = motor.initial_values();
    for (const std::string& s : args->set) {
      const auto eq = s.find('=');
      const int index = eq == std::string::npos ? -1 : param_index(s.substr(0, eq));
      double value = 0;
      const char* first = s.data() + (eq == std::string::npos ? 0 : eq + 1);
      const auto r = std::from_chars(first, s.data() + s.size(), value);
      if (index < 0 || r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(value))
        throw hostio::BadInput("--set " + s + ": expected NAME=VALUE with a known parameter name and a number");
      params[index] = value;
    }
    std::vector<std::filesystem::path> paths(args->data.begin(), args->data.end());
    const data::Dataset dataset = data::load_fleet_dump(paths, with_map(args->map));
    const Model<double> model = motor.model();
    // What lptn inspect --motor would warn of, repeated before the results (one line each, stderr).
    const std::vector<std::string> warnings = model::input_warnings(dataset, motor);
    print_input_warnings(warnings);

    std::unique_ptr<hostio::AtomicDirectory> out;
    if (!args->out.empty()) out = std::make_unique<hostio::AtomicDirectory>(args->out, args->force);
    nlohmann::json j;
    std::vector<model::ErrorMetrics> all_stator, all_rotor;
    if (!args->json) std::printf("%-26s %8s %10s %10s %10s %10s %10s\n", "cycle", "hours", "rmse_st_K", "max_st_K", "bias_st_K", "rmse_rt_K", "max_rt_K");
    for (const data::Cycle& cycle : dataset.cycles) {
      const model::CycleSimulation sim = model::simulate_cycle(model, params, cycle);
      const model::ErrorMetrics st = model::compare(sim.stator_sensor, cycle, data::Channel::stator_winding_c);
      const model::ErrorMetrics rt = model::compare(sim.rotor_sensor, cycle, data::Channel::rotor_c);
      all_stator.push_back(st);
      if (rt.samples) all_rotor.push_back(rt);
      nlohmann::json c = {{"name", cycle.name}, {"stator", metrics_json(st)}};
      if (rt.samples) c["rotor"] = metrics_json(rt);
      j["cycles"].push_back(c);
      if (!args->json) {
        std::printf("%-26s %8.2f %10.3f %10.3f %10.3f ", cycle.name.c_str(), cycle.steps * cycle.dt_s / 3600, st.rmse_k,
                    st.max_abs_k, st.bias_k);
        if (rt.samples) std::printf("%10.3f %10.3f\n", rt.rmse_k, rt.max_abs_k); else std::printf("%10s %10s\n", "-", "-");
      }
      if (out) hostio::write_file_atomically(out->path() / (cycle.name + ".csv"), trace_csv(cycle, sim));
    }
    const model::ErrorMetrics st = model::pool(all_stator), rt = model::pool(all_rotor);
    j["overall"]["stator"] = metrics_json(st);
    if (rt.samples) j["overall"]["rotor"] = metrics_json(rt);
    j["warnings"] = warnings;
    // A model whose temperatures run away (to inf or NaN, or errors no motor survives: an insulation
    // is gone 300 K above its rating) says which of the motor file's values is the likely why.
    constexpr double kRunawayErrorK = 1000;
    const double worst = std::max(st.max_abs_k, rt.samples ? rt.max_abs_k : 0.0);
    if (!(worst < kRunawayErrorK)) {
      const std::string why = model::implausible_values_summary(motor);
      std::fprintf(stderr, "lptn: warning: the model's temperatures run away (error up to %.3g K)%s%s\n", worst,
                   why.empty() ? "" : "; the most implausible value: ", why.c_str());
    }
    if (args->json) {
      std::printf("%s\n", j.dump(2).c_str());
    } else {
      std::printf("%-26s %8s %10.3f %10.3f %10.3f ", "all cycles", "", st.rmse_k, st.max_abs_k, st.bias_k);
      if (rt.samples) std::printf("%10.3f %10.3f\n", rt.rmse_k, rt.max_abs_k); else std::printf("%10s %10s\n", "-", "-");
    }
    if (out) {
      hostio::write_file_atomically(out->path() / "metrics.json", j.dump(2) + "\n");
      out->commit();
      if (!args->json) std::printf("traces and metrics.json written to %s\n", args->out.c_str());
    }
  });
}

}  // namespace lptn::cli
