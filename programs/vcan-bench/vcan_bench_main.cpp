// lptn-vcan-bench: the daemon on a real (virtual) CAN bus against the in-process replay. A test
// bench of this source tree (it runs the scripts beside this file and the daemon built here), so
// it is built here and never installed: the shipped lptn holds no source or build path.
//
// This machine's kernel has no CAN, so the bus lives in a throw-away qemu guest with a Debian
// kernel (programs/vcan-bench/run-guest.sh): canplayer plays the log onto vcan0 (time stamps scaled
// by --time-scale), lptn-daemon reads vcan0 through its kernel filters and sends its frames every
// tick (its timer scaled alike), candump -L records them. Here the recording is decoded through
// the DBC's codecs and compared, tick by tick, with `lptn replay` of the same log.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <stdexcept>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "lptn/firmware/candump_line.hpp"
#include "lptn/firmware/output_frames.hpp"
#include "lptn/can/lptn_frames.hpp"
#include "tools/replay/calibrated_estimator.hpp"
#include "can/bus/bus_map.hpp"
#include "tools/replay/replay_to_csv.hpp"
#include "trainer/calibrate/calibration_file.hpp"

namespace lptn::bench {
namespace {

namespace fs = std::filesystem;

std::string quote(const fs::path& p) { return "'" + p.string() + "'"; }

void shell(const std::string& what, const std::string& cmd) {
  const int status = std::system(cmd.c_str());
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error(what + " failed (exit " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
}


// The replay's estimates and standard deviations by row (ticks since the estimator started).
struct ReplayRow {
  std::array<double, kNumNodes> c{}, sd{};
};

std::vector<ReplayRow> replay_estimates(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string cell; std::getline(header, cell, ',');) names.push_back(cell);
  const char* nodes[kNumNodes] = {"stator_winding", "stator_core", "rotor_winding", "rotor_core"};
  std::size_t est[kNumNodes], sd[kNumNodes];
  auto column = [&](const std::string& name) { return static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin()); };
  for (int i = 0; i < kNumNodes; ++i) {
    est[i] = column(std::string("est_") + nodes[i] + "_c");
    sd[i] = column(std::string("std_") + nodes[i] + "_k");
  }
  std::vector<ReplayRow> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    ReplayRow r;
    for (int i = 0; i < kNumNodes; ++i) {
      r.c[i] = est[i] < cells.size() ? std::stod(cells[est[i]]) : NAN;
      r.sd[i] = sd[i] < cells.size() ? std::stod(cells[sd[i]]) : NAN;
    }
    rows.push_back(r);
  }
  return rows;
}

struct Comparison {
  std::size_t ticks = 0;     // daemon ticks with estimates
  std::size_t compared = 0;  // of those, matched to a replay row
  double max_k[kNumNodes]{};
  double sum_sq[kNumNodes]{};
  double bound_used = 0;  // max over ticks and nodes of |difference| / allowed
  std::size_t status_frames = 0;
  std::size_t uninitialized = 0;  // status frames saying "not initialised"
  unsigned stale_while_uninitialized = 0;  // the stale inputs those frames named, bit per input
};

// The daemon's recording: each tick sends temperatures, ..., innovation (whose ObserverTicks
// counts the ticks since its start), in that order; a tick's temperatures pair with its ticks.
// `ids`: the CAN ids the daemon sends its frames on (the bus map's [outputs]), in
// fw::kOutputFrames' order; a recorded frame on one of them is read as that frame.
Comparison compare(const fs::path& recording, const std::vector<ReplayRow>& replay, double tolerance_k,
                   double tolerance_sigma, const std::array<fw::OutputId, fw::kMaxOutputFrames>& ids) {
  Comparison c;
  std::ifstream in(recording);
  std::array<double, kNumNodes> temps{};
  bool have_temps = false;
  std::size_t wraps = 0;
  int last_ticks = -1;
  for (std::string line; std::getline(in, line);) {
    fw::CandumpRecord rec;
    if (fw::parse_candump_line(line, rec)) continue;
    fw::CanFrame& f = rec.frame;
    for (int k = 0; k < fw::kMaxOutputFrames; ++k)
      if (f.id == ids[static_cast<std::size_t>(k)].id && f.extended == ids[static_cast<std::size_t>(k)].extended) {
        f.id = fw::kOutputFrames[k].dbc.id;  // the DBC's id, which the codecs know it by
        break;
      }
    if (f.id == can::LptnStatus::kId) {
      ++c.status_frames;
      can::LptnStatus st;
      if (st.unpack(f.data, f.len) && st.mode == static_cast<std::uint8_t>(can::LptnStatus::Mode::not_initialized)) {
        ++c.uninitialized;
        c.stale_while_uninitialized |= st.stale_inputs;
      }
    }
    if (f.id == can::LptnTemperatures::kId) {
      can::LptnTemperatures t;
      if (!t.unpack(f.data, f.len)) continue;
      temps = {can::LptnTemperatures::stator_winding_temp_decode(t.stator_winding_temp),
               can::LptnTemperatures::stator_core_temp_decode(t.stator_core_temp),
               can::LptnTemperatures::rotor_winding_temp_decode(t.rotor_winding_temp),
               can::LptnTemperatures::rotor_core_temp_decode(t.rotor_core_temp)};
      have_temps = true;
    } else if (f.id == can::LptnInnovation::kId && have_temps) {
      can::LptnInnovation inn;
      if (!inn.unpack(f.data, f.len)) continue;
      if (static_cast<int>(inn.observer_ticks) < last_ticks) ++wraps;
      last_ticks = inn.observer_ticks;
      const std::size_t k = wraps * 65536 + inn.observer_ticks;
      ++c.ticks;
      have_temps = false;
      if (k >= replay.size()) continue;
      ++c.compared;
      for (int i = 0; i < kNumNodes; ++i) {
        // The daemon's timer has its own phase: a frame may reach it a tick earlier or later than
        // the replay, so its tick k is matched with the nearest of the replay's k-1, k, k+1.
        double d = std::abs(temps[i] - replay[k].c[i]);
        for (std::size_t j : {k - 1, k + 1})
          if (j < replay.size()) d = std::min(d, std::abs(temps[i] - replay[j].c[i]));
        c.max_k[i] = std::max(c.max_k[i], d);
        c.sum_sq[i] += d * d;
        c.bound_used = std::max(c.bound_used, d / (tolerance_k + tolerance_sigma * replay[k].sd[i]));
      }
    }
  }
  return c;
}

// Bad input: one line, exit code 2.
struct BadInput : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void add_options(CLI::App& app) {
  CLI::App* cmd = &app;
  cmd->footer(
      "Boots a throw-away qemu guest (software emulation) with Debian's kernel, loads vcan, plays the log onto vcan0 "
      "with canplayer (time stamps divided by --time-scale), runs lptn-daemon on vcan0 with its timer scaled alike, "
      "records its frames with candump, and compares them tick by tick with `lptn replay` of the same log. Without "
      "--log, generates --minutes of driving and converts it. Needs scripts/setup.sh bench (qemu, busybox, can-utils); "
      "the kernel package is fetched once into --cache. Exit 1 when the daemon's estimates differ from the replay's by "
      "more than --tolerance-k plus --tolerance-sigma of the replay's own standard deviation at any tick, or fewer than 95 % of "
      "its ticks could be compared. Why a tolerance at all: the daemon samples the bus at its own timer's phase, so a "
      "frame may reach it a tick earlier or later than the replay (its ticks are matched with the nearest of the "
      "replay's three around them); a stator reading fused a tick apart meets a slightly different prediction, and "
      "while the filter converges its gain on the unmeasured nodes is large, so the two runs of one filter differ by "
      "a fraction of its own uncertainty. With --open-loop the sensor is not fused and only the inputs' phase remains.");
  struct Args {
    std::string out, log, calibration = LPTN_DEFAULT_CALIBRATION, daemon = LPTN_DAEMON_PATH, bus;
    std::string cache = LPTN_VCAN_CACHE;
    double minutes = 12, time_scale = 10, tolerance_k = 0.1, tolerance_sigma = 0.5;
    bool open_loop = false;
    int timeout_s = 900;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("--out", args->out, "Work directory (log, replay, guest share, recording)")->required();
  cmd->add_option("--log", args->log, "candump -L log to play (default: generate --minutes of driving)");
  cmd->add_option("--minutes", args->minutes, "Minutes of driving to generate without --log")->capture_default_str();
  cmd->add_option("--calibration", args->calibration,
                  "calibration.json for the replay: the one the daemon has compiled in")->capture_default_str();
  cmd->add_option("--daemon", args->daemon, "lptn-daemon to run in the guest")->capture_default_str();
  cmd->add_option("--bus", args->bus,
                  "Bus map (bus.toml) for the replay and the generated log: the one the daemon was built with "
                  "(-DLPTN_BUS); default our own TC_* frames");
  cmd->add_option("--time-scale", args->time_scale, "Play and tick this many times faster than real time")->capture_default_str();
  cmd->add_option("--tolerance-k", args->tolerance_k, "Difference allowed between daemon and replay (K), plus...")
      ->capture_default_str();
  cmd->add_option("--tolerance-sigma", args->tolerance_sigma, "...this share of the replay's standard deviation of the node")
      ->capture_default_str();
  cmd->add_flag("--open-loop", args->open_loop, "Daemon and replay without the stator sensor's correction");
  cmd->add_option("--timeout", args->timeout_s, "Seconds the guest may take")->capture_default_str();
  cmd->add_option("--cache", args->cache, "Where the guest's kernel is kept between runs")->capture_default_str();
  cmd->callback([args] {
    if (!(args->time_scale >= 1 && args->time_scale <= 100)) throw BadInput("--time-scale: between 1 and 100");
    if (!fs::exists(args->daemon)) throw BadInput(args->daemon + ": no such daemon (build lptn-daemon)");
    std::unique_ptr<bus::BusMap> map;
    try {
      if (!args->bus.empty()) map = bus::BusMap::read(args->bus);
    } catch (const bus::MapError& e) {
      throw BadInput(e.what());
    }
    // The ids the daemon sends on: the map's [outputs], or the compiled-in bus's.
    std::array<fw::OutputId, fw::kMaxOutputFrames> outputs{};
    if (map)
      outputs = map->output_ids();
    else
      std::copy(std::begin(lptn::bus::kOutputIds), std::end(lptn::bus::kOutputIds), outputs.begin());
    // candump records exactly those (an 8-digit id is an extended one, candump(1)).
    std::string recorded;
    for (const fw::OutputId& o : outputs) {
      char filter[32];
      std::snprintf(filter, sizeof filter, o.extended ? ",%08X:1FFFFFFF" : ",%03X:7FF", o.id);
      recorded += filter;
    }
    // The daemon filters the map's messages, candump the estimator's outputs.
    const std::size_t filters =
        (map ? map->messages().size() : std::size(lptn::bus::kFilterIds)) + static_cast<std::size_t>(fw::kMaxOutputFrames);
    std::unique_ptr<replay::CalibratedEstimatorConfig> cal;
    try {
      cal = replay::estimator_config_from(load_calibration(args->calibration), args->calibration,
                                  map ? map->decoder() : lptn::bus::decoder());
    } catch (const CalibrationFileError& e) {
      throw BadInput(e.what());
    }
    cal->config.fuse_stator_sensor = !args->open_loop;
    const fs::path out = fs::absolute(args->out);
    fs::create_directories(out);
    const fs::path self = LPTN_BINARY, scripts = LPTN_BENCH_SCRIPTS;

    fs::path log = args->log;
    if (log.empty()) {
      log = out / "drive.log";
      const std::string minutes = std::to_string(args->minutes);
      std::printf("== generate %.0f minutes of driving and convert them to a CAN log\n", args->minutes);
      shell("lptn generate", quote(self) + " generate --out " + quote(out / "data") + " --cycles 1 --seed 21 --minutes-min " +
                                 minutes + " --minutes-max " + minutes + " --force >/dev/null");
      fs::path csv;
      for (const auto& e : fs::directory_iterator(out / "data"))
        if (e.path().extension() == ".csv") csv = e.path();
      shell("lptn convert", quote(self) + " convert --in " + quote(csv) + " --out " + quote(log) +
                                (map ? " --bus " + quote(args->bus) : std::string()) + " --force >/dev/null");
    }
    std::printf("== replay %s in-process\n", log.c_str());
    const fs::path replay_csv = out / "replay.csv";
    fw::ReplayStats stats;
    try {
      stats = replay::replay_to_csv(log.string(), cal->config, replay_csv.string(), true).stats;
    } catch (const std::invalid_argument& e) {
      throw BadInput(e.what());
    }
    const double log_s = static_cast<double>(stats.last_us - stats.first_us) / 1e6;

    std::printf("== the daemon on vcan0 in a qemu guest: %.1f min of log at %gx%s\n", log_s / 60, args->time_scale,
                args->open_loop ? ", open loop" : "");
    const fs::path share = out / "share";
    fs::remove_all(share);
    fs::create_directories(share);
    shell("copying the daemon", quote(scripts / "copy-with-libs.sh") + " " + quote(args->daemon) + " " + quote(share));
    char scale[32];
    std::snprintf(scale, sizeof scale, "%g", args->time_scale);
    shell("scaling the log", "python3 " + quote(scripts / "scale-log.py") + " " + quote(log) + " " + quote(share / "play.log") + " " + scale);
    {
      std::ofstream run(share / "run.sh");
      run << "# The bench payload (lptn-vcan-bench): daemon on vcan0, its frames recorded, the log played.\n"
          << "lptn-daemon --interface vcan0 --time-scale " << scale << (args->open_loop ? " --open-loop" : "")
          << " 2>daemon.err &\n"
          << "daemon=$!\n"
          << "candump -L vcan0" << recorded << " >recording.log &\n"
          << "candump=$!\n"
          // Play only once both listen: the daemon's id filters and candump's show in
          // rcvlist_fil (filtered sockets are not in rcvlist_all).
          << "n=0; until [ $(grep -c '^ *vcan0 ' /proc/net/can/rcvlist_fil) -ge " << filters
          << " ] || [ $n -ge 200 ]; do sleep 0.05; n=$((n+1)); done\n"
          << "canplayer -I play.log vcan0=can0\n"
          << "sleep 1\n"
          << "kill -TERM $daemon\n"
          << "wait $daemon\n"
          << "rc=$?\n"
          << "kill $candump\n"
          << "wait $candump\n"
          << "cat daemon.err\n"
          << "echo \"daemon exit status $rc\"\n"
          << "exit $rc\n";
    }
    shell("the guest", quote(scripts / "run-guest.sh") + " --cache " + quote(args->cache) + " --share " + quote(share) +
                           " --timeout " + std::to_string(args->timeout_s));

    const auto replay = replay_estimates(replay_csv);
    const Comparison c = compare(share / "recording.log", replay, args->tolerance_k, args->tolerance_sigma, outputs);
    const char* names[kNumNodes] = {"stator winding", "stator core", "rotor winding", "rotor core"};
    std::printf("== daemon on vcan0 vs in-process replay: %zu ticks with estimates (replay %zu), %zu compared\n", c.ticks,
                replay.size(), c.compared);
    for (int i = 0; i < kNumNodes; ++i) {
      const double rms = c.compared ? std::sqrt(c.sum_sq[i] / static_cast<double>(c.compared)) : NAN;
      std::printf("   %-15s max |difference| %.3f K, rms %.4f K\n", names[i], c.max_k[i], rms);
    }
    std::printf("   largest difference against what is allowed (%g K + %g sigma): %.0f %%\n", args->tolerance_k,
                args->tolerance_sigma, 100 * c.bound_used);
    std::printf("   status frames %zu, of them %zu not initialised (stale inputs then: mask 0x%03x)\n", c.status_frames,
                c.uninitialized, c.stale_while_uninitialized);
    const bool enough = static_cast<double>(c.compared) >= 0.95 * static_cast<double>(replay.size());
    if (!enough)
      throw std::runtime_error("only " + std::to_string(c.compared) + " of " + std::to_string(replay.size()) +
                               " replay ticks were matched by the daemon's frames; " + std::to_string(c.uninitialized) +
                               " of its " + std::to_string(c.status_frames) +
                               " status frames said not initialised (see " + (share / "daemon.err").string() + " and " +
                               (share / "console.log").string() + ")");
    if (!(c.bound_used <= 1.0))
      throw std::runtime_error("the daemon's estimates differ from the replay's beyond the tolerance (" +
                               std::to_string(100 * c.bound_used) + " % of it)");
    std::printf("vcan bench passed: %s\n", out.c_str());
  });
}

}  // namespace
}  // namespace lptn::bench

int main(int argc, char** argv) {
  CLI::App app{"lptn-vcan-bench: lptn-daemon on vcan0 in a qemu guest against the in-process replay", "lptn-vcan-bench"};
  lptn::bench::add_options(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const lptn::bench::BadInput& e) {
    std::fprintf(stderr, "lptn-vcan-bench: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lptn-vcan-bench: failed: %s\n", e.what());
    return 1;
  }
  return 0;
}
