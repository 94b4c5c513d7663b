// lptn replay: a CAN log (candump, Vector ASC or BLF) through the firmware's estimator, in-process and as fast as the CPU
// allows, the frames' time stamps driving the ticks; the estimates and status as CSV.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "programs/cli/bus_option.hpp"
#include "programs/cli/blas_threads.hpp"
#include "programs/cli/commands.hpp"
#include "hostio/atomic_file.hpp"
#include "hostio/progress_line.hpp"
#include "hostio/worker_threads.hpp"
#include "tools/replay/calibrated_estimator.hpp"
#include "tools/replay/replay_to_csv.hpp"
#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/calibrate/calibration_outcome.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/data/inspection.hpp"
#include "trainer/fleet/fleet_file.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::cli {
namespace {

// What the log sent (`check` was given to replay_to_csv: the last values received at every row,
// plausible or not) against the nameplate of the motor the calibration was made for: another pole
// count (the frequency against the speed), currents or voltages no motor of that nameplate sees.
// A calibration of another motor type gives estimates that look like any others; this is what
// says so. Each finding names the log.
std::vector<std::string> log_against_motor(const std::string& log, const data::NameplateCheck& check,
                                           const calibrate::CalibrationResult& cal, const std::string& source) {
  const std::string who = "cycle " + std::filesystem::path(log).filename().string() + " (" + log + ")";
  std::vector<std::string> out_lines;
  for (const data::Finding& f : check.findings(who))
    out_lines.push_back(f.message + " (the motor of " + source + ": " + cal.motor.name + ")");
  return out_lines;
}

namespace fs = std::filesystem;

// The logs directly in `dir` (*.log, *.asc, *.blf, *.mf4), sorted by name; two that would write the same
// CSV (a.log and a.asc) are bad input.
std::vector<fs::path> logs_in(const fs::path& dir) {
  std::vector<fs::path> logs;
  for (const fs::directory_entry& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && canfile::format_from_extension(e.path())) logs.push_back(e.path());
  std::sort(logs.begin(), logs.end());
  std::map<std::string, fs::path> by_stem;
  for (const fs::path& log : logs) {
    const auto [it, fresh] = by_stem.emplace(log.stem().string(), log);
    if (!fresh)
      throw hostio::BadInput(dir.string() + ": " + it->second.filename().string() + " and " + log.filename().string() +
                     " would both be replayed into " + log.stem().string() + ".csv; replay them apart");
  }
  if (logs.empty()) throw hostio::BadInput("--log " + dir.string() + ": no *.log, *.asc, *.blf or *.mf4 files in this directory");
  return logs;
}

// One log of a directory: its summary and warnings, or the bad input that stopped it.
struct DirectoryItem {
  replay::ReplaySummary summary;
  std::vector<std::string> warnings;
  std::exception_ptr failure;
};

// Every log of `dir` into OUT/NAME.csv, the logs shared over the cores (each log on one thread,
// the next log to whichever thread is free). Each CSV is the bytes a replay of that log alone
// writes. Reported in the order of the names; the first bad log (in that order) is the error, and
// then nothing is written: the CSVs go into a temporary directory renamed into place at the end.
void replay_directory(const fs::path& dir, const std::string& out_dir, bool force, const fw::EstimatorConfig<double>& config,
                      const canfile::LogSelection& select, const calibrate::CalibrationResult& calibrated,
                      const std::string& source, int threads) {
  const std::vector<fs::path> logs = logs_in(dir);
  hostio::AtomicDirectory out(out_dir, force);
  std::vector<DirectoryItem> items(logs.size());
  std::atomic<std::size_t> next{0};
  const auto start = std::chrono::steady_clock::now();
  auto work = [&](std::size_t) {
    for (std::size_t i; (i = next.fetch_add(1)) < logs.size();) {
      DirectoryItem& item = items[i];
      const fs::path csv = out.path() / (logs[i].stem().string() + ".csv");
      try {
        data::NameplateCheck check(calibrated.motor.constants);
        item.summary = replay::replay_to_csv(logs[i].string(), config, csv.string(), true, select, &check);
        item.warnings = fw::input_warnings(logs[i].string(), item.summary.inputs, config);
        for (std::string& w : log_against_motor(logs[i].string(), check, calibrated, source)) item.warnings.push_back(std::move(w));
      } catch (...) {
        item.failure = std::current_exception();
      }
    }
  };
  hostio::parallel_for(static_cast<std::size_t>(std::max(1, threads)), threads, work);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (const DirectoryItem& item : items)
    if (item.failure) std::rethrow_exception(item.failure);
  std::size_t frames = 0, rows = 0;
  for (std::size_t i = 0; i < logs.size(); ++i) {
    const replay::ReplaySummary& r = items[i].summary;
    frames += r.stats.frames;
    rows += r.stats.rows;
    std::printf("[%zu/%zu] %s (%s): %zu frames, %zu estimates%s", i + 1, logs.size(), logs[i].filename().string().c_str(),
                canfile::format_name(r.format), r.stats.frames, r.stats.rows,
                r.stats.bad_records ? (", " + std::to_string(r.stats.bad_records) + " bad records skipped").c_str() : "");
    if (r.stator_samples) std::printf(", stator rmse %.3f K", r.rmse_stator_k);
    if (r.rotor_samples) std::printf(", rotor rmse %.3f K", r.rmse_rotor_k);
    std::printf(" -> %s.csv\n", logs[i].stem().string().c_str());
    for (const std::string& w : items[i].warnings) std::fprintf(stderr, "lptn: warning: %s\n", w.c_str());
  }
  out.commit();
  std::printf("replayed %zu logs of %s: %zu frames, %zu estimates in %.2f s on %d threads, %.0f frames/s -> %s\n",
              logs.size(), dir.string().c_str(), frames, rows, seconds, threads,
              static_cast<double>(frames) / seconds, out_dir.c_str());
}

}  // namespace

void add_replay(CLI::App& app) {
  auto* cmd = app.add_subcommand("replay", "Replay a CAN log (candump, Vector ASC, BLF or MDF4) through the firmware's estimator, "
                                           "as fast as possible");
  cmd->footer(
      "The same estimator as the daemon (firmware/), configured from calibration.json instead of a compiled-in "
      "header. Ticks every 0.1 s from the log's first frame; frames at or before a tick reach it first. One CSV "
      "row per tick once the estimator has started: time_s and the inputs as the model ran on them (fleet-dump "
      "columns, so the CSV loads as a cycle), the four node estimates (est_*_c) and their standard deviations "
      "(std_*_k), the limiting node's margin, mode, stator sensor state, innovation and test ratio, input masks, the "
      "cooling factor with its spread, state and alarm (LPTN_Cooling). "
      "The log's format is --format, else its content's (BLF's \"LOGG\", MDF4's identification block, a candump "
      "line, an ASC header), else its extension's (.log candump, .asc, .blf, .mf4); a file in none is one error line. --channel picks one bus of a "
      "log that holds several; without it every channel's frames are read as one bus, with a warning. Malformed lines (BLF: objects; MDF4: records and blocks, by byte offset) are reported with their number and skipped, the first ten "
      "of them one by one, then as a count. "
      "--log DIR replays every *.log, *.asc, *.blf and *.mf4 in DIR into --out DIR/NAME.csv, several logs at once "
      "(--threads, default one per core), each CSV the bytes a replay of that log alone writes; a line per log in the "
      "order of the names, then the total. A bad log is reported as for one log (the first by name) and then no CSV is "
      "written.");
  struct Args {
    std::string log, calibration, fleet, out, format, channel, bus;
    bool open_loop = false, use_actor = false, force = false, quiet = false;
    int threads = 0;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("--log", args->log,
                  "CAN log: candump -L, Vector ASC, BLF or MDF4 (e.g. from lptn convert or a drive's recorder); or a "
                  "directory: every *.log, *.asc, *.blf and *.mf4 in it into --out/NAME.csv, the logs shared over the cores")
      ->required();
  cmd->add_option("--format", args->format, "The log's format: candump, asc, blf or mdf4 (default: detected)")
      ->check(CLI::IsMember({"candump", "asc", "blf", "mdf4"}));
  cmd->add_option("--channel", args->channel,
                  "Only the frames of this channel (candump: an interface name; ASC, BLF, MDF4: a number); default all");
  auto* calibration = cmd->add_option("--calibration", args->calibration, "calibration.json (from lptn calibrate)");
  auto* fleet = cmd->add_option("--fleet", args->fleet,
                                "fleet.json (from lptn calibrate --fleet): the motor type's pooled calibration, as "
                                "flashed into every motor of the type; the on-board cooling factor then says how "
                                "this motor differs");
  calibration->excludes(fleet);
  fleet->excludes(calibration);
  cmd->add_option("--bus", args->bus,
                  "Bus map (bus.toml) naming the converter DBC's messages and signals that carry each input "
                  "(default: our own TC_* frames, can/codecs/bus.toml)");
  cmd->add_option("--out", args->out, "CSV of estimates and status to write; a directory if --log is one")->required();
  cmd->add_option("--threads", args->threads, "--log DIR: how many logs at once (default: one per core)")
      ->check(CLI::Range(1, 256));
  cmd->add_flag("--open-loop", args->open_loop, "Do not fuse the stator winding sensor (the model alone)");
  cmd->add_flag("--use-actor", args->use_actor, "Let the calibration's TD3 actor schedule the parameters");
  cmd->add_flag("--force", args->force, "Replace --out if it exists");
  cmd->add_flag("--quiet", args->quiet, "No progress line");
  cmd->callback([args] {
    stop_blas_threads();
    // Inputs, then the output, before any work (a missing input is the first thing to hear of).
    check_input_path(args->log, "--log", InputPath::file_or_directory);
    const bool directory = fs::is_directory(args->log);
    if (directory && fs::exists(args->out) && fs::equivalent(args->log, args->out))
      throw hostio::BadInput("--out " + args->out + ": is the --log directory");
    if (!directory && args->threads != 0) throw hostio::BadInput("--threads applies to a directory of logs (--log DIR)");
    if (!args->calibration.empty()) check_input_path(args->calibration, "--calibration", InputPath::file);
    if (!args->fleet.empty()) check_input_path(args->fleet, "--fleet", InputPath::file);
    if (!args->bus.empty()) check_input_path(args->bus, "--bus", InputPath::file);
    check_output_path(args->out, args->force);
    // A bad map or calibration file is bad input (main.cpp reports CalibrationFileError as such).
    const std::unique_ptr<bus::BusMap> map = args->bus.empty() ? nullptr : read_bus_map(args->bus);
    if (args->calibration.empty() && args->fleet.empty())
      throw hostio::BadInput("replay: --calibration or --fleet is required (see --help)");
    const std::string& source = args->fleet.empty() ? args->calibration : args->fleet;
    const calibrate::CalibrationResult calibrated =
        args->fleet.empty() ? calibrate::load_calibration(args->calibration) : fleet::load_fleet_file(args->fleet).pooled;
    // What a converter flashed with it would estimate: a calibration that is not ok says so first.
    if (const std::string caution = calibrate::status_caution(calibrated, source, true); !caution.empty())
      std::fprintf(stderr, "lptn: warning: %s\n", caution.c_str());
    const auto cal = replay::estimator_config_from(calibrated, source, map ? map->decoder() : lptn::bus::decoder());
    if (args->use_actor && !cal->config.actor.actor)
      throw hostio::BadInput(source + ": --use-actor: this calibration has no actor");
    // A type's pooled calibration: this motor may differ from the type by the fleet's scatter.
    if (!args->fleet.empty()) cal->config.observer.cooling_initial_std = fw::ObserverSettings<double>{}.cooling_initial_std;
    cal->config.fuse_stator_sensor = !args->open_loop;
    cal->config.use_actor = args->use_actor;
    const canfile::LogSelection select{args->format.empty() ? std::nullopt : canfile::format_from_name(args->format),
                                       args->channel};
    // Bad input throws BadInput or std::invalid_argument, which run_cli reports alike (exit 2).
    if (directory) {
      replay_directory(args->log, args->out, args->force, cal->config, select, calibrated, source,
                       args->threads ? args->threads : hostio::worker_threads());
      return;
    }
    data::NameplateCheck check(calibrated.motor.constants);
    const replay::ReplaySummary r = replay::replay_to_csv(args->log, cal->config, args->out, args->quiet, select, &check);
    const fw::ReplayStats& s = r.stats;
    std::printf("replayed %s (%s): %zu frames, %s of log, %zu estimates%s -> %s\n", args->log.c_str(),
                canfile::format_name(r.format), s.frames,
                hostio::ProgressLine::clock(static_cast<double>(s.last_us - s.first_us) / 1e6).c_str(), s.rows,
                s.bad_records ? (", " + std::to_string(s.bad_records) + " bad records skipped").c_str() : "",
                args->out.c_str());
    std::printf("  %.2f s, %.0f frames/s\n", r.seconds, static_cast<double>(s.frames) / r.seconds);
    if (r.stator_samples)
      std::printf("  stator winding estimate vs its sensor%s: rmse %.3f K\n", args->open_loop ? " (open loop)" : " (fused)",
                  r.rmse_stator_k);
    if (r.rotor_samples)
      std::printf("  rotor winding estimate vs rotor telemetry (never fused): rmse %.3f K\n", r.rmse_rotor_k);
    // The spread's honesty: how often the +-2 sigma band (widened by the telemetry's own noise)
    // holds the reading. Fused, the stator estimate follows its sensor, so its figure says less.
    auto coverage = [](const char* what, const replay::BandCoverage& c) {
      if (c.ticks == 0) return;
      std::printf("  %s: +-2 sigma covers the telemetry on %.1f %% of %zu ticks (|estimate - reading| <= "
                  "2 sqrt(sigma^2 + noise^2), noise %.2f K from the log)\n",
                  what, 100.0 * c.share(), c.ticks, c.sensor_noise_k);
    };
    coverage(args->open_loop ? "stator winding (open loop)" : "stator winding (fused: follows this sensor)",
             r.stator_coverage);
    coverage("rotor winding (never fused)", r.rotor_coverage);
    if (r.cooling_state != fw::CoolingState::off)
      std::printf("  cooling factor at the end %.3f +- %.3f (%s); cooling alarm %s\n", r.cooling_factor,
                  r.cooling_factor_std, r.cooling_state == fw::CoolingState::tracking ? "tracking" : "frozen: open loop",
                  r.cooling_alarm_from_s < 0 ? "never raised"
                                             : ("raised from " + hostio::ProgressLine::clock(r.cooling_alarm_from_s)).c_str());
    for (const std::string& w : fw::input_warnings(args->log, r.inputs, cal->config))
      std::fprintf(stderr, "lptn: warning: %s\n", w.c_str());
    for (const std::string& w : log_against_motor(args->log, check, calibrated, source))
      std::fprintf(stderr, "lptn: warning: %s\n", w.c_str());
  });
}

}  // namespace lptn::cli
