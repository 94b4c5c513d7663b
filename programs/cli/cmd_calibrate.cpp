// lptn calibrate: fit the model to a fleet dump with Levenberg-Marquardt (Ceres) or TD3 (libtorch,
// in lptn-td3) and write calibration.json (docs/calibration.md).
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "hostio/process_group.hpp"
#include "hostio/progress_line.hpp"
#include "programs/cli/commands.hpp"
#include "programs/cli/exit_code.hpp"
#include "trainer/calibrate/calibration_outcome.hpp"
#include "trainer/calibrate/calibration_result.hpp"
#include "trainer/lm/lm.hpp"
#include "trainer/lm/lm_result.hpp"
#include "trainer/calibrate/shared_dataset.hpp"
#include "programs/cli/data_map_option.hpp"
#include "trainer/data/inspection.hpp"
#include "trainer/fleet/fleet_file.hpp"
#include "trainer/model/motor_effects.hpp"
#include "trainer/data/sensor_fault.hpp"
#include "trainer/model/motor_plausibility.hpp"
#include "trainer/search/search.hpp"

namespace lptn::cli {
namespace {

void run_lm(const CalibrateArgs& a, const MotorFile& motor, const data::Dataset& dataset, const Split& split,
            CalibrationResult& r) {
  LmSettings settings;
  settings.judge_identifiability = true;  // what the data cannot pin stays the motor file's, said so
  ProgressLine line(a.quiet);
  const LmReport rep = fit_lm(motor, motor.initial_values(), dataset, split.train, settings,
                              [&](int it, double rmse, double seconds) {
                                char buf[160];
                                std::snprintf(buf, sizeof buf, "lm: iteration %3d  rmse %8.4f K  %s", it, rmse,
                                              ProgressLine::clock(seconds).c_str());
                                line.update(buf, true);
                              });
  line.finish();
  record_lm_fit(r, rep, FreeParameters::from_motor(motor), r.train_cycles, to_json(settings));
}

// Random search or CMA-ES: the benchmark's baselines beside TD3 (no libtorch).
void run_search(const CalibrateArgs& a, const MotorFile& motor, const data::Dataset& dataset, const Split& split,
                CalibrationResult& r) {
  const search::SearchMethod method = a.method == "cma-es" ? search::SearchMethod::cma_es : search::SearchMethod::random;
  search::SearchSettings settings;
  settings.seed = a.seed;
  if (a.budget_steps > 0) settings.budget_steps = a.budget_steps;
  ProgressLine line(a.quiet);
  const search::SearchOutcome o = search::search_calibration(method, motor, dataset, split.train, settings,
                                             [&](std::size_t steps, std::size_t budget, double best, double seconds) {
                                               const double done = std::min(1.0, double(steps) / double(budget));
                                               char buf[200];
                                               std::snprintf(buf, sizeof buf, "%s: %5.1f G of %.1f G model steps %s best %.4f K  %s elapsed",
                                                             to_string(method), steps / 1e9, budget / 1e9,
                                                             ProgressLine::bar(done).c_str(), best, ProgressLine::clock(seconds).c_str());
                                               line.update(buf, done >= 1.0);
                                             });
  line.finish();
  for (int i = 0; i < kNumParams; ++i) r.parameters[static_cast<std::size_t>(i)].value = o.values[i];
  r.method = to_string(method);
  r.settings = to_json(settings);
  r.details = {{"simulated_steps", o.simulated_steps}, {"evaluations", o.evaluations}, {"best_train_rmse_k", o.best_train_rmse_k},
               {"result", "the best of the three best sets scored on the training grid, re-scored on the data's own grid with the "
                          "metrics' start offsets"}};
  r.seconds = o.seconds;
}

#if LPTN_WITH_TD3
// lptn holds no libtorch (it would cost every command, `lptn --help` included, half a second to
// load): TD3 runs in lptn-td3, installed beside lptn, given this very command line.
[[noreturn]] void hand_over_to_td3_program() {
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe");
  const std::filesystem::path program = self.parent_path() / "lptn-td3";
  std::vector<std::string> args = invocation();
  args[0] = program.string();
  std::vector<char*> argv;
  for (std::string& s : args) argv.push_back(s.data());
  argv.push_back(nullptr);
  std::fflush(stdout);
  ::execv(program.c_str(), argv.data());
  throw std::runtime_error(program.string() + ": cannot run it (" + std::strerror(errno) +
                           "); lptn-td3 is installed beside lptn where lptn is built with TD3");
}
#endif

void print_metrics(const char* side, const SplitMetrics& m);

// The exit code a calibration's status gives (exit_code.hpp).
int exit_code_of(const CalibrationResult& r) {
  return r.status == kStatusFailed ? kExitFailed : (r.status == kStatusWarnings ? kExitWarnings : 0);
}

// The warnings go to stderr, quiet or not: a script that ignores stdout must still see them. The
// data's were printed before the work began.
void print_outcome_warnings(const CalibrationResult& r) {
  for (const CalibrationWarning& w : r.warnings)
    if (w.code != "data") std::fprintf(stderr, "lptn: warning: %s\n", w.message.c_str());
}

// What of the input makes the calibration doubtful, for its status: the data against the motor's
// nameplate (another pole count, a channel's scaling), the motor file's implausible values, and
// columns the loader ignored (a misnamed rotor column drops the rotor data). Gaps the loader bridged,
// masked or split as the data contract says are printed but make no calibration doubtful.
std::vector<std::string> doubtful_input(const data::Dataset& dataset, const MotorFile& motor) {
  std::vector<std::string> out;
  for (const data::CycleReport& r : dataset.reports)
    for (const data::Finding& f : r.findings)
      if (f.severity == data::Finding::Severity::warning && f.message.find("; ignored") != std::string::npos)
        out.push_back(f.message);
  for (const data::Finding& f : data::check_against_nameplate(dataset, motor.constants))
    if (f.severity == data::Finding::Severity::warning) out.push_back(f.message);
  for (std::string& w : motor_warnings(motor)) out.push_back(std::move(w));
  return out;
}

// The model ran away at the motor file's values: bad input, naming the most implausible value.
BadInput not_simulable(const std::string& path, const MotorFile& motor, const ModelNotSimulable& e) {
  const std::string why = implausible_values_summary(motor);
  return BadInput(path + ": " + e.what() + (why.empty() ? std::string() : "; the most implausible value: " + why));
}

// --fleet: the motor type over every motor, each motor's cooling factor, the outliers (fleet.json).
void run_fleet(const CalibrateArgs& a, const MotorFile& motor, const ProcessGroup& group) {
  const fleet::FleetDump fleet = fleet::load_shared_fleet(a.fleet, group, with_map(a.map));
  const Split split = split_cycles(fleet.dataset, a.test_cycles, a.test_fraction, a.seed);
  CalibrationResult r = new_calibration(motor, a.motor, fleet.dataset, split);
  if (!a.quiet)
    std::printf("calibrating %s over a fleet of %zu motors: the type on %zu cycles (testing on %zu, %s), each motor's "
                "cooling on all of its own\n",
                motor.name.c_str(), fleet.motor_ids.size(), split.train.size(), split.test.size(), split.rule.c_str());
  std::fflush(stdout);
  fleet::FleetSettings settings;
  settings.lm.judge_identifiability = true;
  ProgressLine line(a.quiet);
  fleet::FleetFit fit;
  try {
    fit = fleet::fit_fleet(motor, fleet, split.train, settings, [&](const std::string& s) { line.update(s, true); });
  } catch (const ModelNotSimulable& e) {
    throw not_simulable(a.motor, motor, e);
  }
  line.finish();
  record_lm_fit(r, fit.shared, FreeParameters::from_motor(motor), r.train_cycles, to_json(settings.lm));
  r.seconds = fit.seconds;
  score_calibration(r, motor, fleet.dataset, split);
  if (group.leads()) print_input_warnings(input_warnings(fleet.dataset, motor));
  const std::vector<std::string> inspected = doubtful_input(fleet.dataset, motor);
  judge_outcome(r, inspected);
  set_exit_code(exit_code_of(r));
  if (!group.leads()) return;
  fleet::save_fleet(a.out, r, fit, settings);
  print_outcome_warnings(r);
  if (a.quiet) return;
  std::vector<ErrorMetrics> stator, rotor;
  for (const fleet::FleetMotorResult& m : fit.motors) {
    stator.push_back(m.metrics.stator);
    rotor.push_back(m.metrics.rotor);
  }
  const ErrorMetrics all_stator = pool(stator), all_rotor = pool(rotor);
  std::printf("each motor with its own cooling factor, all %zu cycles: stator rmse %.3f K", fleet.dataset.cycles.size(),
              all_stator.rmse_k);
  if (all_rotor.samples) std::printf(", rotor rmse %.3f K", all_rotor.rmse_k);
  std::printf("\nthe type as if one motor had driven every cycle:\n");
  print_metrics("train", r.train);
  if (!r.test.cycles.empty()) print_metrics("test", r.test);
  std::printf("%-10s %8s %8s %7s %10s  %s\n", "motor", "cooling", "+-", "cycles", "stator", "verdict");
  for (const fleet::FleetMotorResult& m : fit.motors)
    std::printf("%-10s %8.3f %8.4f %7zu %8.3f K  %s%s\n", m.id.c_str(), m.cooling_factor, m.cooling_factor_std,
                m.metrics.cycles.size(), m.metrics.stator.rmse_k, m.verdict.outlier ? "OUTLIER: " : "",
                m.verdict.reason.c_str());
  std::printf("%s written (%d rounds, %.1f s)\n", a.out.c_str(), fit.rounds, fit.seconds);
}

void print_metrics(const char* side, const SplitMetrics& m) {
  std::printf("%-6s stator rmse %.3f K  max %.3f K  bias %+.3f K", side, m.stator.rmse_k, m.stator.max_abs_k, m.stator.bias_k);
  if (m.rotor.samples) std::printf(" | rotor rmse %.3f K  max %.3f K", m.rotor.rmse_k, m.rotor.max_abs_k);
  std::printf("  (%zu cycles)\n", m.cycles.size());
}

void run(const CalibrateArgs& given, Td3Calibrator td3) {
  // LM shares its work over the processes of an MPI job, if one started this; rank 0 speaks and writes.
  // TD3 does not: every rank would train the same agent and write the same files.
  const bool search = given.method == "random-search" || given.method == "cma-es";
  if (given.method != "lm" && launched_by_mpi())
    throw BadInput("--method " + given.method + ": not shared over MPI processes (only --method lm is); run it without mpirun");
  const ProcessGroup& group = given.method == "lm" ? ProcessGroup::world() : ProcessGroup::alone();
  CalibrateArgs a = given;
  a.quiet = a.quiet || !group.leads();
  if (!a.quiet && group.shared())
    std::printf("sharing the work over %d processes (MPI): each loads and simulates its own %s\n", group.size(),
                a.fleet.empty() ? "files" : "motors");
  if (a.method != "lm" && !search && td3 == nullptr) {
#if LPTN_WITH_TD3
    hand_over_to_td3_program();
#else
    throw BadInput("--method " + a.method + ": this lptn was built without libtorch (LPTN_WITH_TD3=OFF); only --method lm is available");
#endif
  }
  std::vector<int> added;  // the arguments themselves first, before any file is looked at
  for (const std::string& name : a.effects) added.push_back(effect_by_name(name, "--effect"));
  // Inputs next (a missing one is the first thing to hear of), then the output, before any work.
  for (const std::string& d : a.data) check_input_path(d, "--data");
  if (!a.fleet.empty()) check_input_path(a.fleet, "--fleet", InputPath::directory);
  check_input_path(a.motor, "--motor", InputPath::file);
  check_output_path(a.out, a.force);
  MotorFile motor = load_motor_file(a.motor);
  for (int e : added) enable_effect(motor, e);
  if (!a.fleet.empty()) {
    if (!a.sensor_faults.empty()) throw BadInput("--sensor-fault: not with --fleet (a fault is one motor's sensor)");
    return run_fleet(a, motor, group);
  }
  std::vector<std::filesystem::path> paths(a.data.begin(), a.data.end());
  data::Dataset dataset = load_shared_dump(paths, group, with_map(a.map));
  try {
    data::correct_readings(dataset, a.sensor_faults);
  } catch (const std::invalid_argument& e) {
    throw BadInput(std::string("--sensor-fault: ") + e.what());
  }
  const Split split = split_cycles(dataset, a.test_cycles, a.test_fraction, a.seed);
  balance_training(dataset, split.train, group);  // only LM runs shared
  // What `lptn inspect --motor` would say of this data and motor file, repeated here, once, and
  // carried into calibration.json's warnings.
  if (group.leads()) print_input_warnings(input_warnings(dataset, motor));
  const std::vector<std::string> inspected = doubtful_input(dataset, motor);

  // LM judges what the data pins as it fits; the other methods would move a parameter the data
  // cannot see at random and call it calibrated: it stays the motor file's, said so.
  std::vector<NotIdentifiable> unseen;
  try {
    if (a.method != "lm") unseen = unseen_parameters(motor, motor.initial_values(), dataset, split.train);
  } catch (const ModelNotSimulable& e) {
    throw not_simulable(a.motor, motor, e);
  }
  for (const NotIdentifiable& n : unseen) motor.parameters[static_cast<std::size_t>(n.index)].calibrate = false;
  CalibrationResult r = new_calibration(motor, a.motor, dataset, split);
  r.sensor_faults = a.sensor_faults;
  mark_not_identifiable(r, unseen);
  if (!a.quiet)
    std::printf("calibrating %s with %s on %zu cycles, testing on %zu (%s)\n", motor.name.c_str(), a.method.c_str(),
                split.train.size(), split.test.size(), split.rule.c_str());
  std::fflush(stdout);  // before the progress lines on stderr

  try {
    if (a.method == "lm") run_lm(a, motor, dataset, split, r);
    else if (search) run_search(a, motor, dataset, split, r);
    else td3(a, motor, dataset, split, r);
  } catch (const ModelNotSimulable& e) {
    throw not_simulable(a.motor, motor, e);
  }

  score_calibration(r, motor, dataset, split);
  judge_outcome(r, inspected);
  set_exit_code(exit_code_of(r));
  if (!group.leads()) return;
  save_calibration(r, a.out);
  if (!a.quiet) {
    for (const ParameterResult& p : r.parameters) {
      if (!p.calibrated && p.identifiable) continue;
      std::printf("  %-24s %12.5g %-8s", p.name.c_str(), p.value, p.unit.c_str());
      if (!p.identifiable) {
        std::printf("   not identifiable: the motor file's value\n");
        continue;
      }
      if (std::isfinite(p.std_error)) std::printf(" +- %.3g", p.std_error);
      std::printf("   (start %g)%s\n", p.initial, at_bound(p) ? "   AT ITS BOUND" : "");
    }
    for (const CorrelatedPair& c : r.correlated)
      std::printf("  note: %s and %s are %+.3f correlated: this data pins their combination better than either\n", c.a.c_str(), c.b.c_str(), c.correlation);
    print_metrics("train", r.train);
    if (!r.test.cycles.empty()) print_metrics("test", r.test);
  }
  print_outcome_warnings(r);
  if (!a.quiet || r.status != kStatusOk) {
    if (r.status == kStatusFailed)
      std::printf("%s written with status FAILED, for inspection only (lptn export refuses it): %zu warning%s above\n",
                  a.out.c_str(), r.warnings.size(), r.warnings.size() == 1 ? "" : "s");
    else if (r.status == kStatusWarnings)
      std::printf("%s written with status warnings (%zu; read them before using it; %.1f s of calibration)\n", a.out.c_str(),
                  r.warnings.size(), r.seconds);
    else
      std::printf("%s written, status ok (%.1f s of calibration)\n", a.out.c_str(), r.seconds);
  }
}

}  // namespace

void add_calibrate(CLI::App& app, Td3Calibrator td3) {
  auto* cmd = app.add_subcommand("calibrate", "Fit the model's parameters to a fleet dump (LM or TD3) and write calibration.json; under "
                                                 "`mpirun -np N`, LM shares the files (or --fleet's motors) over N processes");
  auto a = std::make_shared<CalibrateArgs>();
  auto* data = cmd->add_option("--data", a->data, "Directories of cycle CSVs, or CSV files")->expected(1, -1);
  auto* fleet = cmd->add_option("--fleet", a->fleet,
                                "A fleet: FLEET/<motor_id>/*.csv, one motor type; writes fleet.json (docs/fleet.md), --method lm");
  add_map_option(cmd, a->map);
  data->excludes(fleet);
  fleet->excludes(data);
  cmd->add_option("--motor", a->motor, "Motor file: constants, effects, which parameters to calibrate and their bounds")->required();
  cmd->add_option("--method", a->method, "lm (Levenberg-Marquardt, Ceres), td3 (an agent that steps through parameter sets), td3-paper (the paper's per-step agent), "
                  "td3-episode (one action per episode), or the baselines random-search and cma-es")
      ->check(CLI::IsMember({"lm", "td3", "td3-paper", "td3-episode", "random-search", "cma-es"}));
  cmd->add_option("--out", a->out, "The calibration file to write (JSON, docs/calibration.md)")->required();
  cmd->add_option("--effect", a->effects,
                  "Add an effect to those the motor file enables, with the library's parameter settings (repeatable or comma-separated)")
      ->delimiter(',');
  cmd->add_option("--sensor-fault", a->sensor_faults,
                  "A sensor fault to take out of the readings before the fit, SENSOR:SHAPE:SIZE:FIRST as lptn diagnose "
                  "prints it (stator:offset:+3.02:cycle_05_freight; docs/diagnosis.md); kept in the calibration, and "
                  "diagnose, check and report correct the readings likewise (repeatable)");
  cmd->add_option("--test-cycles", a->test_cycles, "Cycles held out for testing, by name (comma-separated)")->delimiter(',');
  cmd->add_option("--test-fraction", a->test_fraction, "Otherwise this fraction of the cycles, drawn with --seed (default 1/3)");
  auto* seed = cmd->add_option("--seed", a->seed, "Seed of the split and of TD3 (a run is repeatable)");
  cmd->add_option("--config", a->config, "TD3 settings (TOML; docs/td3.toml lists every key for td3, docs/td3-paper.toml for td3-paper and td3-episode)");
  cmd->add_option("--episodes", a->episodes, "TD3: stop after this many episodes (overrides max_episodes)");
  cmd->add_option("--budget-steps", a->budget_steps,
                  "random-search, cma-es: model steps to spend (default 1.8e9, about what td3 spends with its defaults)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--checkpoint-dir", a->checkpoint_dir, "TD3 checkpoints (default: OUT.checkpoints)");
  cmd->add_flag("--resume", a->resume, "TD3: continue after the last checkpoint");
  cmd->add_option("--warm-start", a->warm_start,
                  "td3: start from the agent of an earlier td3 calibration (its JSON; the agent file it names lies beside it)");
  cmd->add_flag("--test-curve", a->test_curve,
                "td3: after training, score the best set of every checkpoint on the test cycles (method.details.test_curve; "
                "the benchmark's time to target; training never sees them)");
  cmd->add_flag("--force", a->force, "Replace --out if it exists");
  cmd->add_flag("--quiet", a->quiet, "No progress output");
  cmd->callback([a, seed, td3] {
    a->seed_given = seed->count() > 0;
    if (a->data.empty() && a->fleet.empty()) throw BadInput("calibrate: give --data (one motor) or --fleet (many)");
    if (!a->fleet.empty() && a->method != "lm")
      throw BadInput("--fleet: only --method lm calibrates a fleet (its per-motor factors are LM fits)");
    if ((!a->warm_start.empty() || a->test_curve) && a->method != "td3")
      throw BadInput(std::string(a->warm_start.empty() ? "--test-curve" : "--warm-start") + ": only with --method td3");
    run(*a, td3);
  });
}

}  // namespace lptn::cli
