// lptn calibrate: fit the model to a fleet dump with Levenberg-Marquardt (Ceres), the search
// baselines, or TD3 (libtorch, in lptn-td3) and write calibration.json (docs/calibration.md). The
// work is trainer/workflow's; this file reads the arguments, prints and writes.
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "hostio/process_group.hpp"
#include "hostio/progress_line.hpp"
#include "programs/cli/commands.hpp"
#include "programs/cli/data_map_option.hpp"
#include "programs/cli/exit_code.hpp"
#include "trainer/calibrate/calibration_outcome.hpp"
#include "trainer/fleet/fleet_file.hpp"
#include "trainer/workflow/calibrate.hpp"

namespace lptn::cli {
namespace {

struct CalibrateArgs {
  calibrate::CalibrationRequest request;
  bool force = false, quiet = false;
};

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

// The exit code a calibration's status gives (exit_code.hpp).
int exit_code_of(const calibrate::CalibrationResult& r) {
  return r.status == calibrate::kStatusFailed ? kExitFailed : (r.status == calibrate::kStatusWarnings ? kExitWarnings : 0);
}

// The warnings go to stderr, quiet or not: a script that ignores stdout must still see them. The
// data's were printed before the work began.
void print_outcome_warnings(const calibrate::CalibrationResult& r) {
  for (const calibrate::CalibrationWarning& w : r.warnings)
    if (w.code != "data") std::fprintf(stderr, "lptn: warning: %s\n", w.message.c_str());
}

// The line that ends a calibration, a motor's or a fleet's: where it went and its status. `took`:
// how long, in words ("9.6 s of calibration").
void print_written(const std::string& out, const calibrate::CalibrationResult& r, const char* took) {
  if (r.status == calibrate::kStatusFailed)
    std::printf("%s written with status FAILED, for inspection only (lptn export refuses it): %zu warning%s above\n",
                out.c_str(), r.warnings.size(), r.warnings.size() == 1 ? "" : "s");
  else if (r.status == calibrate::kStatusWarnings)
    std::printf("%s written with status warnings (%zu; read them before using it; %s)\n", out.c_str(), r.warnings.size(), took);
  else
    std::printf("%s written, status ok (%s)\n", out.c_str(), took);
}

void print_metrics(const char* side, const calibrate::SplitMetrics& m) {
  std::printf("%-6s stator rmse %.3f K  max %.3f K  bias %+.3f K", side, m.stator.rmse_k, m.stator.max_abs_k, m.stator.bias_k);
  if (m.rotor.samples) std::printf(" | rotor rmse %.3f K  max %.3f K", m.rotor.rmse_k, m.rotor.max_abs_k);
  std::printf("  (%zu cycles)\n", m.cycles.size());
}

// The workflow's events as lptn prints them: the inspection's warnings on stderr (the first
// process's), the plan on stdout, progress on one status line.
workflow::CalibrationEvents printed_events(const CalibrateArgs& a, const hostio::ProcessGroup& group, hostio::ProgressLine& line) {
  workflow::CalibrationEvents events;
  events.input_warnings = [&group](const std::vector<std::string>& warnings) {
    if (group.leads()) print_input_warnings(warnings);
  };
  events.started = [&a](const workflow::CalibrationPlan& p) {
    if (!a.quiet) {
      if (p.motors > 0)
        std::printf("calibrating %s over a fleet of %zu motors: the type on %zu cycles (testing on %zu, %s), each motor's "
                    "cooling on all of its own\n",
                    p.motor_name.c_str(), p.motors, p.train_cycles, p.test_cycles, p.split_rule.c_str());
      else
        std::printf("calibrating %s with %s on %zu cycles, testing on %zu (%s)\n", p.motor_name.c_str(), p.method.c_str(),
                    p.train_cycles, p.test_cycles, p.split_rule.c_str());
    }
    std::fflush(stdout);  // before the progress lines on stderr
  };
  events.progress = [&line](const std::string& text, bool done) { line.update(text, done); };
  return events;
}

// --fleet: the motor type over every motor, each motor's cooling factor, the outliers (fleet.json).
void run_fleet(const CalibrateArgs& a, const hostio::ProcessGroup& group) {
  hostio::ProgressLine line(a.quiet);
  const workflow::FleetCalibration f = workflow::calibrate_fleet(a.request, printed_events(a, group, line));
  line.finish();
  const calibrate::CalibrationResult& r = f.result;
  set_exit_code(exit_code_of(r));
  if (!group.leads()) return;
  fleet::save_fleet(a.request.out, r, f.fit, f.settings);
  print_outcome_warnings(r);
  if (a.quiet) return;
  std::vector<ErrorMetrics> stator, rotor;
  for (const fleet::FleetMotorResult& m : f.fit.motors) {
    stator.push_back(m.metrics.stator);
    rotor.push_back(m.metrics.rotor);
  }
  const ErrorMetrics all_stator = pool(stator), all_rotor = pool(rotor);
  std::printf("each motor with its own cooling factor, all %zu cycles: stator rmse %.3f K", f.cycles, all_stator.rmse_k);
  if (all_rotor.samples) std::printf(", rotor rmse %.3f K", all_rotor.rmse_k);
  std::printf("\nthe type as if one motor had driven every cycle:\n");
  print_metrics("train", r.train);
  if (!r.test.cycles.empty()) print_metrics("test", r.test);
  std::printf("%-10s %8s %8s %7s %10s  %s\n", "motor", "cooling", "+-", "cycles", "stator", "verdict");
  for (const fleet::FleetMotorResult& m : f.fit.motors)
    std::printf("%-10s %8.3f %8.4f %7zu %8.3f K  %s%s\n", m.id.c_str(), m.cooling_factor, m.cooling_factor_std,
                m.metrics.cycles.size(), m.metrics.stator.rmse_k, m.verdict.outlier ? "OUTLIER: " : "",
                m.verdict.reason.c_str());
  char took[64];
  std::snprintf(took, sizeof took, "%d rounds, %.1f s", f.fit.rounds, f.fit.seconds);
  print_written(a.request.out, r, took);
}

void run(const CalibrateArgs& given, calibrate::CalibrationMethod td3) {
  const calibrate::CalibrationRequest& q = given.request;
#if LPTN_WITH_TD3
  if (workflow::is_td3(q.method) && td3 == nullptr && !hostio::launched_by_mpi()) hand_over_to_td3_program();
#else
  if (workflow::is_td3(q.method) && td3 == nullptr)
    throw hostio::BadInput("--method " + q.method + ": this lptn was built without libtorch (LPTN_WITH_TD3=OFF); only --method lm is available");
#endif
  workflow::check_request(q, td3);  // the arguments themselves first, before any file is looked at
  // LM shares its work over the processes of an MPI job, if one started this; rank 0 speaks and writes.
  const hostio::ProcessGroup& group = workflow::calibration_group(q.method);
  CalibrateArgs a = given;
  a.quiet = a.quiet || !group.leads();
  if (!a.quiet && group.shared())
    std::printf("sharing the work over %d processes (MPI): each loads and simulates its own %s\n", group.size(),
                q.fleet.empty() ? "files" : "motors");
  // Inputs next (a missing one is the first thing to hear of), then the output, before any work.
  for (const std::string& d : q.data) check_input_path(d, "--data");
  if (!q.fleet.empty()) check_input_path(q.fleet, "--fleet", InputPath::directory);
  check_input_path(q.motor, "--motor", InputPath::file);
  if (!q.map.empty()) check_input_path(q.map, "--map", InputPath::file);
  check_output_path(q.out, a.force);
  if (!q.fleet.empty()) return run_fleet(a, group);

  hostio::ProgressLine line(a.quiet);
  const calibrate::CalibrationResult r = workflow::calibrate(q, printed_events(a, group, line), td3);
  line.finish();
  set_exit_code(exit_code_of(r));
  if (!group.leads()) return;
  calibrate::save_calibration(r, q.out);
  if (!a.quiet) {
    for (const calibrate::ParameterResult& p : r.parameters) {
      if (!p.calibrated && p.identifiable) continue;
      std::printf("  %-24s %12.5g %-8s", p.name.c_str(), p.value, p.unit.c_str());
      if (!p.identifiable) {
        std::printf("   not identifiable: the motor file's value\n");
        continue;
      }
      if (std::isfinite(p.std_error)) std::printf(" +- %.3g", p.std_error);
      std::printf("   (start %g)%s\n", p.initial, calibrate::at_bound(p) ? "   AT ITS BOUND" : "");
    }
    for (const calibrate::CorrelatedPair& c : r.correlated)
      std::printf("  note: %s and %s are %+.3f correlated: this data pins their combination better than either\n", c.a.c_str(), c.b.c_str(), c.correlation);
    print_metrics("train", r.train);
    if (!r.test.cycles.empty()) print_metrics("test", r.test);
  }
  print_outcome_warnings(r);
  char took[64];
  std::snprintf(took, sizeof took, "%.1f s of calibration", r.seconds);
  if (!a.quiet || r.status != calibrate::kStatusOk) print_written(q.out, r, took);
}

}  // namespace

void add_calibrate(CLI::App& app, calibrate::CalibrationMethod td3) {
  auto* cmd = app.add_subcommand("calibrate", "Fit the model's parameters to a fleet dump (LM or TD3) and write calibration.json; under "
                                                 "`mpirun -np N`, LM shares the files (or --fleet's motors) over N processes");
  auto a = std::make_shared<CalibrateArgs>();
  calibrate::CalibrationRequest& q = a->request;
  auto* data = cmd->add_option("--data", q.data, "Directories of cycle CSVs, or CSV files")->expected(1, -1);
  auto* fleet = cmd->add_option("--fleet", q.fleet,
                                "A fleet: FLEET/<motor_id>/*.csv, one motor type; writes fleet.json (docs/fleet.md), --method lm");
  add_map_option(cmd, q.map);
  data->excludes(fleet);
  fleet->excludes(data);
  cmd->add_option("--motor", q.motor, "Motor file: constants, effects, which parameters to calibrate and their bounds")->required();
  cmd->add_option("--method", q.method, "lm (Levenberg-Marquardt, Ceres), td3 (an agent that steps through parameter sets), td3-paper (the paper's per-step agent), "
                  "td3-episode (one action per episode), or the baselines random-search and cma-es")
      ->check(CLI::IsMember(std::vector<std::string>(workflow::kMethods.begin(), workflow::kMethods.end())));
  cmd->add_option("--out", q.out, "The calibration file to write (JSON, docs/calibration.md)")->required();
  cmd->add_option("--effect", q.effects,
                  "Add an effect to those the motor file enables, with the library's parameter settings (repeatable or comma-separated)")
      ->delimiter(',');
  cmd->add_option("--sensor-fault", q.sensor_faults,
                  "A sensor fault to take out of the readings before the fit, SENSOR:SHAPE:SIZE:FIRST as lptn diagnose "
                  "prints it (stator:offset:+3.02:cycle_05_freight; docs/diagnosis.md); kept in the calibration, and "
                  "diagnose, check and report correct the readings likewise (repeatable)");
  cmd->add_option("--test-cycles", q.test_cycles, "Cycles held out for testing, by name (comma-separated)")->delimiter(',');
  cmd->add_option("--test-fraction", q.test_fraction, "Otherwise this fraction of the cycles, drawn with --seed (default 1/3)");
  auto* seed = cmd->add_option("--seed", q.seed, "Seed of the split and of TD3 (a run is repeatable)");
  cmd->add_option("--config", q.td3_config, "TD3 settings (TOML; docs/td3.toml lists every key for td3, docs/td3-paper.toml for td3-paper and td3-episode)");
  cmd->add_option("--episodes", q.episodes, "TD3: stop after this many episodes (overrides max_episodes)");
  cmd->add_option("--budget-steps", q.budget_steps,
                  "random-search, cma-es: model steps to spend (default 1.8e9, about what td3 spends with its defaults)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--checkpoint-dir", q.checkpoint_dir, "TD3 checkpoints (default: OUT.checkpoints)");
  cmd->add_flag("--resume", q.resume, "TD3: continue after the last checkpoint");
  cmd->add_option("--warm-start", q.warm_start,
                  "td3: start from the agent of an earlier td3 calibration (its JSON; the agent file it names lies beside it)");
  cmd->add_flag("--test-curve", q.test_curve,
                "td3: after training, score the best set of every checkpoint on the test cycles (method.details.test_curve; "
                "the benchmark's time to target; training never sees them)");
  cmd->add_flag("--force", a->force, "Replace --out if it exists");
  cmd->add_flag("--quiet", a->quiet, "No progress output");
  cmd->callback([a, seed, td3] {
    a->request.seed_given = seed->count() > 0;
    run(*a, td3);
  });
}

}  // namespace lptn::cli
