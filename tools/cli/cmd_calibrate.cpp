// lptn calibrate: fit the model to a fleet dump with Levenberg-Marquardt (Ceres) or TD3 (libtorch)
// and write calibration.json (docs/calibration.md).
#include <chrono>
#include <cmath>
#include <map>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "tools/cli/commands.hpp"
#include "tools/cli/progress.hpp"
#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/calibrate/lm.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/diagnose/diagnose.hpp"
#include "trainer/model/motor_file.hpp"
#if LPTN_WITH_TD3
#include "trainer/td3/td3_calibration.hpp"
#endif

namespace lptn::cli {
namespace {

struct Args {
  std::vector<std::string> data;
  std::string motor, method = "lm", out, config, checkpoint_dir;
  std::vector<std::string> test_cycles, effects;
  double test_fraction = 1.0 / 3.0;
  std::uint64_t seed = 1;
  int episodes = 0;
  bool resume = false, force = false, quiet = false, seed_given = false;
};

// The files behind the cycles, hashed, and one hash over them all (in cycle order).
void describe_data(const data::Dataset& dataset, CalibrationResult& r) {
  std::map<std::string, std::string> hashes;
  std::string all;
  for (const data::Cycle& c : dataset.cycles) {
    const std::string file = c.file.string();
    if (!hashes.count(file)) hashes[file] = sha256_file(c.file);
    r.data.push_back({c.name, c.file.filename().string(), hashes[file]});
    all += hashes[file];
  }
  r.data_sha256 = sha256_hex(all.data(), all.size());
}

nlohmann::json lm_settings_json(const LmSettings& s) {
  return {{"max_iterations", s.max_iterations}, {"function_tolerance", s.function_tolerance},
          {"parameter_tolerance", s.parameter_tolerance}, {"threads", s.threads},
          {"correlation_flag", s.correlation_flag}, {"initial_offsets", "estimated per cycle (stator core, rotor core)"}};
}

void run_lm(const Args& a, const MotorFile& motor, const data::Dataset& dataset, const Split& split, CalibrationResult& r) {
  LmSettings settings;
  ProgressLine line(a.quiet);
  const LmReport rep = fit_lm(motor, motor.initial_values(), dataset, split.train, settings,
                              [&](int it, double rmse, double seconds) {
                                char buf[160];
                                std::snprintf(buf, sizeof buf, "lm: iteration %3d  rmse %8.4f K  %s", it, rmse,
                                              ProgressLine::clock(seconds).c_str());
                                line.update(buf, true);
                              });
  line.finish();
  const FreeParameters free = FreeParameters::from_motor(motor);
  for (int i = 0; i < kNumParams; ++i) {
    r.parameters[static_cast<std::size_t>(i)].value = rep.values[i];
    r.parameters[static_cast<std::size_t>(i)].std_error = rep.std_error[i];
  }
  r.correlated = rep.correlated;
  r.method = "lm";
  r.settings = lm_settings_json(settings);
  nlohmann::json offsets = nlohmann::json::array();
  for (std::size_t i = 0; i < split.train.size(); ++i)
    offsets.push_back({{"cycle", dataset.cycles[split.train[i]].name},
                       {"stator_core_k", rep.offsets[i].stator_core},
                       {"rotor_core_k", rep.offsets[i].rotor_core}});
  nlohmann::json at_bound = nlohmann::json::array();
  for (std::size_t j = 0; j < free.size(); ++j)
    if (rep.at_bound[j]) at_bound.push_back(std::string(param_spec(free.index[j]).name));
  nlohmann::json names = nlohmann::json::array();
  for (int i : free.index) names.push_back(std::string(param_spec(i).name));
  r.details = {{"iterations", rep.iterations},   {"converged", rep.converged},
               {"termination", rep.termination}, {"initial_cost_k2", rep.initial_cost},
               {"final_cost_k2", rep.final_cost}, {"residuals", rep.residuals},
               {"rmse_k", rep.rmse_k},           {"correlation_time", rep.correlation_time},
               {"at_bound", at_bound},           {"correlation", {{"parameters", names}, {"matrix", rep.correlation}}},
               {"initial_offsets", offsets}};
  r.seconds = rep.seconds;
}

#if LPTN_WITH_TD3
void run_td3(const Args& a, td3::Formulation formulation, const MotorFile& motor, const data::Dataset& dataset,
             const Split& split, CalibrationResult& r) {
  td3::TrainingSettings settings =
      a.config.empty() ? td3::default_settings(formulation) : td3::load_settings(a.config, formulation);
  if (a.config.empty() || a.seed_given) settings.seed = settings.agent.seed = a.seed;  // --seed wins over the file
  if (a.episodes > 0) settings.max_episodes = a.episodes;
  bool rotor = false;
  for (std::size_t c : split.train) rotor = rotor || dataset.cycles[c].has(data::Channel::rotor_c);
  if (!rotor) settings.reward.w3 = 0.0;  // eq. 15 without the rotor term where the rotor is not measured
  const std::filesystem::path checkpoints = a.checkpoint_dir.empty() ? std::filesystem::path(a.out + ".checkpoints") : std::filesystem::path(a.checkpoint_dir);
  ProgressLine line(a.quiet);
  const td3::Td3Outcome o = td3::train_td3(motor, dataset, split.train, settings, checkpoints, a.resume,
                                           [&](const td3::EpisodeReport& e) {
                                             char buf[200];
                                             std::snprintf(buf, sizeof buf, "%s: episode %4d/%d %s reward %7.3f  average %7.3f  %s elapsed, ~%s left%s",
                                                           td3::to_string(formulation), e.episode, e.max_episodes,
                                                           ProgressLine::bar(double(e.episode) / e.max_episodes).c_str(),
                                                           e.reward, e.average, ProgressLine::clock(e.seconds).c_str(),
                                                           ProgressLine::clock(e.seconds_left).c_str(), e.random ? " (random actions)" : "");
                                             line.update(buf, e.episode == e.max_episodes);
                                             return true;
                                           });
  line.finish();
  for (int i = 0; i < kNumParams; ++i) r.parameters[static_cast<std::size_t>(i)].value = o.values[i];
  r.method = td3::to_string(formulation);
  r.settings = td3::to_json(settings);
  nlohmann::json curve = nlohmann::json::array();
  for (const td3::EpisodeRecord& e : o.curve) curve.push_back(td3::to_json(e));
  r.details = {{"episodes", o.episodes},
               {"initial_evaluation", o.initial_evaluation},
               {"reached_target", o.reached_target},
               {"resumed_from_episode", o.resumed_from},
               {"checkpoints", checkpoints.string()},
               {"constant_set", "policy over the training data's operating points, tanh outputs averaged, mapped onto the bounds; "
                                "of the checkpoints' sets the one with the lowest training RMSE (episode 0: the starting guess)"},
               {"best_episode", o.best_episode},
               {"best_train_rmse_k", o.best_train_rmse_k},
               {"training_curve", curve}};
  r.seconds = o.seconds;
  r.has_actor = true;
  ActorExport& x = r.actor;
  x.obs_offset = {0.0, 0.0};
  x.obs_scale = o.obs_scale;
  x.layers = {{o.actor.inputs, o.actor.hidden, o.actor.w1, o.actor.b1},
              {o.actor.hidden, o.actor.hidden, o.actor.w2, o.actor.b2},
              {o.actor.hidden, o.actor.outputs, o.actor.w3, o.actor.b3}};
  x.param_indices = o.param_indices;
  x.check_obs = o.check_obs;
  x.check_actions = o.check_actions;
}
#endif  // LPTN_WITH_TD3

void print_metrics(const char* side, const SplitMetrics& m) {
  std::printf("%-6s stator rmse %.3f K  max %.3f K  bias %+.3f K", side, m.stator.rmse_k, m.stator.max_abs_k, m.stator.bias_k);
  if (m.rotor.samples) std::printf(" | rotor rmse %.3f K  max %.3f K", m.rotor.rmse_k, m.rotor.max_abs_k);
  std::printf("  (%zu cycles)\n", m.cycles.size());
}

}  // namespace

void add_calibrate(CLI::App& app) {
  auto* cmd = app.add_subcommand("calibrate", "Fit the model's parameters to a fleet dump (LM or TD3) and write calibration.json");
  auto a = std::make_shared<Args>();
  cmd->add_option("--data", a->data, "Directories of cycle CSVs, or CSV files")->required()->expected(1, -1);
  cmd->add_option("--motor", a->motor, "Motor file: constants, effects, which parameters to calibrate and their bounds")->required();
  cmd->add_option("--method", a->method, "lm (Levenberg-Marquardt, Ceres), td3 (the paper's per-step agent) or td3-episode (one action per episode)")
      ->check(CLI::IsMember({"lm", "td3", "td3-episode"}));
  cmd->add_option("--out", a->out, "The calibration file to write (JSON, docs/calibration.md)")->required();
  cmd->add_option("--effect", a->effects,
                  "Add an effect to those the motor file enables, with the library's parameter settings (repeatable or comma-separated)")
      ->delimiter(',');
  cmd->add_option("--test-cycles", a->test_cycles, "Cycles held out for testing, by name (comma-separated)")->delimiter(',');
  cmd->add_option("--test-fraction", a->test_fraction, "Otherwise this fraction of the cycles, drawn with --seed (default 1/3)");
  auto* seed = cmd->add_option("--seed", a->seed, "Seed of the split and of TD3 (a run is repeatable)");
  cmd->add_option("--config", a->config, "TD3 settings (TOML; docs/td3.toml lists every key)");
  cmd->add_option("--episodes", a->episodes, "TD3: stop after this many episodes (overrides max_episodes)");
  cmd->add_option("--checkpoint-dir", a->checkpoint_dir, "TD3 checkpoints (default: OUT.checkpoints)");
  cmd->add_flag("--resume", a->resume, "TD3: continue after the last checkpoint");
  cmd->add_flag("--force", a->force, "Replace --out if it exists");
  cmd->add_flag("--quiet", a->quiet, "No progress output");
  cmd->callback([a, seed] {
    a->seed_given = seed->count() > 0;
#if !LPTN_WITH_TD3
    if (a->method != "lm")
      throw BadInput("--method " + a->method + ": this lptn was built without libtorch (LPTN_WITH_TD3=OFF); only --method lm is available");
#endif
    refuse_overwrite(a->out, a->force);
    std::vector<int> added;  // checked before any file is read
    for (const std::string& name : a->effects) added.push_back(diagnose::effect_by_name(name, "--effect"));
    MotorFile motor = load_motor_file(a->motor);
    for (int e : added) diagnose::enable_effect(motor, e);
    std::vector<std::filesystem::path> paths(a->data.begin(), a->data.end());
    const data::Dataset dataset = data::load_fleet_dump(paths);
    const Split split = split_cycles(dataset, a->test_cycles, a->test_fraction, a->seed);

    CalibrationResult r;
    r.created_utc = utc_now();
    r.lptn_version = "lptn 0.1.0";
    r.motor_name = motor.name;
    r.motor_file = a->motor;
    r.motor_text = motor.text;
    r.effects = motor.effects;
    const ParamVector<double> start = motor.initial_values();
    for (int i = 0; i < kNumParams; ++i) {
      const ParameterSetting& s = motor.parameters[static_cast<std::size_t>(i)];
      ParameterResult p;
      p.name = param_spec(i).name;
      p.unit = param_spec(i).unit;
      p.value = p.initial = start[i];
      p.min = s.min;
      p.max = s.max;
      const int effect = effect_of_param(i);
      p.calibrated = s.calibrate && (effect < 0 || (motor.effects & effect_bit(effect)));
      r.parameters.push_back(p);
    }
    describe_data(dataset, r);
    for (std::size_t c : split.train) r.train_cycles.push_back(dataset.cycles[c].name);
    for (std::size_t c : split.test) r.test_cycles.push_back(dataset.cycles[c].name);
    r.split_rule = split.rule;
    if (!a->quiet)
      std::printf("calibrating %s with %s on %zu cycles, testing on %zu (%s)\n", motor.name.c_str(), a->method.c_str(),
                  split.train.size(), split.test.size(), split.rule.c_str());
    std::fflush(stdout);  // before the progress lines on stderr

    if (a->method == "lm") run_lm(*a, motor, dataset, split, r);
#if LPTN_WITH_TD3
    else run_td3(*a, a->method == "td3" ? td3::Formulation::per_step : td3::Formulation::episode, motor, dataset, split, r);
#endif

    const Model<double> model = motor.model();
    r.train = evaluate_split(model, r.values(), dataset, split.train);
    r.test = evaluate_split(model, r.values(), dataset, split.test);
    save_calibration(r, a->out);
    if (!a->quiet) {
      for (const ParameterResult& p : r.parameters) {
        if (!p.calibrated) continue;
        std::printf("  %-24s %12.5g %-8s", p.name.c_str(), p.value, p.unit.c_str());
        if (std::isfinite(p.std_error)) std::printf(" +- %.3g", p.std_error);
        std::printf("   (start %g)\n", p.initial);
      }
      for (const CorrelatedPair& c : r.correlated)
        std::printf("  note: %s and %s are %+.3f correlated: this data pins their combination better than either\n", c.a.c_str(), c.b.c_str(), c.correlation);
      print_metrics("train", r.train);
      if (!r.test.cycles.empty()) print_metrics("test", r.test);
      std::printf("%s written (%.1f s of calibration)\n", a->out.c_str(), r.seconds);
    }
  });
}

}  // namespace lptn::cli
