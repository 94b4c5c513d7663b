// Golden tests of the on-board estimator against the trainer and against itself:
//  - open loop, `lptn replay` of a CAN log is the trainer's simulation (trainer/model/simulate)
//    of the same inputs, within 1e-3 K over a whole cycle;
//  - the header-built firmware (lptn-daemon, calibration compiled in) writes exactly the CSV that
//    `lptn replay` writes with the same calibration loaded from JSON;
//  - the daemon's timer loop on a paced log sends what the replay computes, tick for tick;
//  - the committed header is the export of the committed calibration.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "lptn_testing/run_lptn.hpp"
#include "lptn_testing/temp_dir.hpp"
#include "lptn_testing/csv_columns.hpp"
#include "firmware/linux/record.hpp"
#include "lptn/firmware/candump_line.hpp"
#include "lptn/can/lptn_frames.hpp"
#include "tools/replay/calibrated_estimator.hpp"
#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/model/motor_file.hpp"
#include "trainer/model/simulate.hpp"

namespace lptn::replay {
namespace {

namespace fs = std::filesystem;

const fs::path kCalibration = fs::path(LPTN_SOURCE_DIR) / "firmware/calibration/default_calibration.json";
const fs::path kHeader = fs::path(LPTN_SOURCE_DIR) / "firmware/calibration/default_calibration.hpp";

using testing::slurp;

struct Outcome {
  int code;
  std::string err;
};

Outcome run(const std::string& binary, const std::string& args, const fs::path& scratch) {
  const fs::path err = scratch / "stderr.txt";
  const std::string cmd = binary + " " + args + " >" + (scratch / "stdout.txt").string() + " 2>" + err.string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(err)};
}

const auto read_csv = lptn::testing::read_csv_columns;

// One generated cycle of 25-30 minutes as a CAN log, shared by the tests.
class ReplayGolden : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir;
    const fs::path d = dir_->path();
    const auto g = testing::generate_cycle(d, 11, 25, 30);
    ASSERT_EQ(g.generate.code, 0) << g.generate.err;
    ASSERT_FALSE(g.csv.empty());
    const Outcome convert = run(LPTN_BINARY, "convert --in " + g.csv.string() + " --out " + log().string(), d);
    ASSERT_EQ(convert.code, 0) << convert.err;
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path dir() { return dir_->path(); }
  static fs::path log() { return dir() / "cycle.log"; }

  static testing::TempDir* dir_;
};
testing::TempDir* ReplayGolden::dir_ = nullptr;

TEST_F(ReplayGolden, OpenLoopReplayIsTheTrainersSimulationOfTheSameInputs) {
  const fs::path out = dir() / "open.csv";
  const Outcome r = run(LPTN_BINARY, "replay --quiet --open-loop --log " + log().string() + " --calibration " +
                                     kCalibration.string() + " --out " + out.string(), dir());
  ASSERT_EQ(r.code, 0) << r.err;

  // The replay's CSV is a fleet-dump cycle of the inputs the firmware ran on: load it as the
  // trainer loads any cycle and simulate it with the calibration's model.
  const data::Dataset ds = data::load_cycle_file(out);
  ASSERT_EQ(ds.cycles.size(), 1u) << "one unbroken cycle";
  const data::Cycle& cycle = ds.cycles[0];
  const calibrate::CalibrationResult cal = calibrate::load_calibration(kCalibration);
  const Model<double> model(cal.motor.constants, cal.effects);
  const model::CycleSimulation sim = model::simulate_cycle(model, cal.values(), cycle);

  const auto csv = read_csv(out);
  const char* columns[kNumNodes] = {"est_stator_winding_c", "est_stator_core_c", "est_rotor_winding_c", "est_rotor_core_c"};
  ASSERT_EQ(csv.at(columns[0]).size(), cycle.steps);
  ASSERT_GT(cycle.steps, 25u * 600u);
  double worst = 0;
  for (int i = 0; i < kNumNodes; ++i)
    for (std::size_t k = 0; k < cycle.steps; ++k) worst = std::max(worst, std::abs(csv.at(columns[i])[k] - sim.nodes[i][k]));
  std::printf("open-loop replay vs trainer simulation: %zu steps, max |difference| %.2e K\n", cycle.steps, worst);
  EXPECT_LT(worst, 1e-3);
  // Not trivially equal: the cycle heats the motor.
  const auto& winding = csv.at(columns[0]);
  EXPECT_GT(*std::max_element(winding.begin(), winding.end()) - winding.front(), 10.0);
}

TEST_F(ReplayGolden, HeaderBuiltFirmwareWritesExactlyWhatTheJsonLoadedReplayWrites) {
  for (const std::string mode : {"", "--open-loop "}) {
    const fs::path json = dir() / "json.csv", header = dir() / "header.csv";
    const Outcome a = run(LPTN_BINARY, "replay --quiet --force " + mode + "--log " + log().string() + " --calibration " +
                                       kCalibration.string() + " --out " + json.string(), dir());
    ASSERT_EQ(a.code, 0) << a.err;
    const Outcome b = run(LPTN_DAEMON, "--replay " + log().string() + " " + mode + "--csv " + header.string(), dir());
    ASSERT_EQ(b.code, 0) << b.err;
    const std::string x = slurp(json), y = slurp(header);
    EXPECT_GT(x.size(), 1000000u);
    EXPECT_TRUE(x == y) << "the two CSVs differ (" << mode << ")";
  }
}

// The stator sensor's frames (TC_StatorTemp) gone from the log's second half: the daemon's replay
// says so as `lptn replay` does, in the same words after each program's "warning:"; the whole log
// gives neither a line.
TEST_F(ReplayGolden, TheDaemonSaysWhichInputsDidNotReachTheModelAsReplayDoes) {
  std::vector<std::string> lines;
  {
    std::ifstream in(log());
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  ASSERT_GT(lines.size(), 10000u);
  const fs::path silent = dir() / "stator_silent.log";
  {
    std::ofstream out(silent);
    char hex[16];  // candump -L: " 130#<data>", the id in hex
    std::snprintf(hex, sizeof hex, " %03X#", static_cast<unsigned>(can::TcStatorTemp::kId));
    for (std::size_t k = 0; k < lines.size(); ++k)
      if (k < lines.size() / 2 || lines[k].find(hex) == std::string::npos) out << lines[k] << '\n';
  }
  for (const fs::path& l : {log(), silent}) {
    const Outcome a = run(LPTN_BINARY, "replay --quiet --force --log " + l.string() + " --calibration " +
                                       kCalibration.string() + " --out " + (dir() / "a.csv").string(), dir());
    ASSERT_EQ(a.code, 0) << a.err;
    const Outcome b = run(LPTN_DAEMON, "--replay " + l.string() + " --csv " + (dir() / "b.csv").string(), dir());
    ASSERT_EQ(b.code, 0) << b.err;
    auto said = [&](const std::string& err) {
      std::string lines_said;
      std::istringstream in(err);
      for (std::string line; std::getline(in, line);)
        if (line.find("did not reach the model as sent") != std::string::npos)
          lines_said += line.substr(line.find(l.string())) + "\n";  // after the program's "<name>: warning: "
      return lines_said;
    };
    const std::string x = said(a.err), y = said(b.err);
    EXPECT_EQ(x, y) << "lptn replay:\n" << a.err << "lptn-daemon --replay:\n" << b.err;
    if (l == log()) {
      EXPECT_EQ(y, "") << b.err;
    } else {
      EXPECT_NE(y.find(l.string() + ": input stator_sensor did not reach the model as sent: stale"), std::string::npos) << b.err;
      EXPECT_NE(y.find("those rows went without its readings"), std::string::npos) << b.err;
    }
  }
}

TEST_F(ReplayGolden, TheCommittedHeaderIsTheExportOfTheCommittedCalibration) {
  const fs::path out = dir() / "default_calibration.hpp";
  ASSERT_EQ(run(LPTN_BINARY, "export --calibration " + kCalibration.string() + " --out " + out.string(), dir()).code, 0);
  EXPECT_TRUE(slurp(out) == slurp(kHeader))
      << "firmware/calibration/default_calibration.hpp is stale: lptn export --calibration default_calibration.json";
}

// The daemon's own loop (a monotonic timer, missed ticks caught up), fed the log at 1000x: every
// tick's frames carry the replay's estimate, to the frames' resolution.
TEST_F(ReplayGolden, TheDaemonsTimerLoopSendsWhatTheReplayComputes) {
  const fs::path replay = dir() / "closed.csv", frames = dir() / "daemon.log";
  ASSERT_EQ(run(LPTN_DAEMON, "--replay " + log().string() + " --csv " + replay.string(), dir()).code, 0);
  const Outcome r = run(LPTN_DAEMON, "--log " + log().string() + " --time-scale 1000 --out " + frames.string(), dir());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto csv = read_csv(replay);
  const auto& winding = csv.at("est_stator_winding_c");
  const auto& core = csv.at("est_rotor_core_c");
  std::ifstream in(frames);
  std::size_t k = 0, seen = 0;
  double worst = 0;
  for (std::string line; std::getline(in, line);) {
    fw::CandumpRecord rec;
    ASSERT_EQ(fw::parse_candump_line(line, rec), nullptr) << line;
    if (rec.frame.id != can::LptnTemperatures::kId) continue;
    can::LptnTemperatures t;
    ASSERT_TRUE(t.unpack(rec.frame.data, rec.frame.len));
    ASSERT_LT(k, winding.size());
    worst = std::max(worst, std::abs(can::LptnTemperatures::stator_winding_temp_decode(t.stator_winding_temp) - winding[k]));
    worst = std::max(worst, std::abs(can::LptnTemperatures::rotor_core_temp_decode(t.rotor_core_temp) - core[k]));
    ++k;
    ++seen;
  }
  EXPECT_EQ(seen, winding.size()) << "one temperature frame per estimate";
  // Rounding to the frames' resolution (lptn.dbc's factor, 0.05 K) is the whole difference.
  const double resolution = can::LptnTemperatures::stator_winding_temp_decode(1) -
                            can::LptnTemperatures::stator_winding_temp_decode(0);
  EXPECT_LE(worst, resolution / 2 + 1e-9) << "the frames' resolution is " << resolution << " K";
}

// The daemon's record (--record) holds what its estimator was given: the log's frames, in order,
// and every tick's frames as the daemon sent them; an estimator configured from the JSON
// calibration, fed the record, makes those frames bit for bit. A record with one received byte
// changed does not, so the check can fail.
TEST_F(ReplayGolden, TheDaemonsRecordReplaysToItsFramesBitForBit) {
  const fs::path frames = dir() / "recorded_run.log", record = dir() / "record.log";
  const Outcome r = run(LPTN_DAEMON, "--log " + log().string() + " --time-scale 1000 --out " + frames.string() +
                                         " --record " + record.string(), dir());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto lines = [](const fs::path& file, std::string_view interface) {
    std::vector<std::pair<fw::TimeUs, std::string>> out;  // time stamp, frame text
    std::ifstream in(file);
    for (std::string line; std::getline(in, line);) {
      fw::CandumpRecord rec;
      if (fw::parse_candump_line(line, rec) != nullptr || (!interface.empty() && rec.interface != interface)) continue;
      out.emplace_back(rec.time_us, line.substr(line.rfind(' ') + 1));
    }
    return out;
  };
  const auto played = lines(log(), ""), received = lines(record, "rx"), sent = lines(frames, "lptn"),
             recorded = lines(record, "tx");
  ASSERT_FALSE(played.empty());
  EXPECT_EQ(received, played) << "the record's received frames are the log's, with the log's time stamps";
  ASSERT_FALSE(sent.empty());
  EXPECT_EQ(recorded, sent) << "the record's tick frames are the frames the daemon sent";

  const auto config = replay::estimator_config_from(calibrate::load_calibration(kCalibration), kCalibration.string());
  fw::Estimator<double> estimator(config->config);
  const fw::RecordReplay replayed = fw::replay_record(record, estimator, lptn::bus::kOutputIds);
  EXPECT_EQ(replayed.received, played.size());
  EXPECT_GT(replayed.ticks, 10000u);
  EXPECT_EQ(replayed.ticks_differing, 0u) << "first at tick " << replayed.first_differing;
  EXPECT_EQ(replayed.bad_lines, 0u);

  // One received current byte changed, a third of the way in: from there the estimates differ.
  std::string text = slurp(record);
  const std::size_t at = text.find(" rx 101#", text.size() / 3);
  ASSERT_NE(at, std::string::npos);
  char& digit = text[at + 8 + 10];  // StatorCurrent's high byte (the sixth), its high nibble (lptn.dbc)
  digit = digit == '7' ? '1' : '7';
  const fs::path altered = dir() / "record_altered.log";
  std::ofstream(altered) << text;
  fw::Estimator<double> again(config->config);
  const fw::RecordReplay differing = fw::replay_record(altered, again, lptn::bus::kOutputIds);
  EXPECT_GT(differing.ticks_differing, 0u);
  EXPECT_GT(differing.first_differing, replayed.ticks / 4);
}

// A converter that never sends its fast frame (speed, current, frequency): the daemon never starts
// its estimator, and says so on stderr once frames have arrived for a while, not only in the status
// frames it sends, and counts the ticks without estimates when it stops.
TEST_F(ReplayGolden, TheDaemonSaysWhyItSendsNoEstimates) {
  const fs::path without = dir() / "without_fast_frame.log", frames = dir() / "no_estimates.log";
  {
    std::ifstream in(log());
    std::ofstream out(without);
    std::size_t dropped = 0;
    for (std::string line; std::getline(in, line);) {
      fw::CandumpRecord rec;
      ASSERT_EQ(fw::parse_candump_line(line, rec), nullptr) << line;
      if (rec.frame.id == can::TcElectrical::kId) {
        ++dropped;
        continue;
      }
      out << line << "\n";
    }
    ASSERT_GT(dropped, 100u);
  }
  const Outcome r = run(LPTN_DAEMON, "--log " + without.string() + " --time-scale 1000 --out " + frames.string(), dir());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: no estimates after 10 s of frames"), std::string::npos) << r.err;
  std::size_t temperatures = 0;
  std::ifstream in(frames);
  for (std::string line; std::getline(in, line);) {
    fw::CandumpRecord rec;
    ASSERT_EQ(fw::parse_candump_line(line, rec), nullptr) << line;
    temperatures += rec.frame.id == can::LptnTemperatures::kId;
  }
  EXPECT_EQ(temperatures, 0u);
  // "stopped after N ticks (N without estimates)": every tick.
  const std::size_t at = r.err.find("stopped after ");
  ASSERT_NE(at, std::string::npos) << r.err;
  const unsigned long long ticks = std::stoull(r.err.substr(at + 14));
  EXPECT_NE(r.err.find("(" + std::to_string(ticks) + " without estimates)"), std::string::npos) << r.err;
}

// The schedule follows the daemon's own word, not a wall time guessed for this machine: SIGTERM
// goes one second after the daemon said it started its loop (however long the start took on a
// loaded machine), and what it sent is held to the ticks it says it ran.
TEST_F(ReplayGolden, TheDaemonStopsCleanlyOnSigterm) {
  const fs::path frames = dir() / "sigterm.log", err = dir() / "sigterm.err";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const std::string out = frames.string(), in = log().string();
    std::freopen(err.c_str(), "w", stderr);
    execl(LPTN_DAEMON, LPTN_DAEMON, "--log", in.c_str(), "--out", out.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  const auto wait_start = std::chrono::steady_clock::now();
  while (slurp(err).find(", tick 100 ms") == std::string::npos &&
         std::chrono::steady_clock::now() - wait_start < std::chrono::minutes(2))
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const auto started = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::seconds(1));
  ASSERT_EQ(kill(pid, SIGTERM), 0);
  const double ran_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  int status = 0;
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(1)) << "stops between two ticks";
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  const std::string said = slurp(err);
  unsigned long long ticks = 0;
  const std::size_t at = said.find("stopped after ");
  ASSERT_NE(at, std::string::npos) << said;
  ASSERT_EQ(std::sscanf(said.c_str() + at, "stopped after %llu ticks", &ticks), 1) << said;
  // A late wake-up runs the missed ticks, so a second of loop is ten ticks however loaded the
  // machine: never more than the time allows, and at least half of it.
  EXPECT_GE(ticks, 5u);
  EXPECT_LE(static_cast<double>(ticks), ran_s / 0.1 + 2) << ran_s << " s";
  // What it had sent is there, whole: a status frame for every tick it ran.
  std::ifstream in(frames);
  std::size_t status_frames = 0;
  for (std::string line; std::getline(in, line);) {
    fw::CandumpRecord rec;
    ASSERT_EQ(fw::parse_candump_line(line, rec), nullptr) << line;
    if (rec.frame.id == can::LptnStatus::kId) ++status_frames;
  }
  EXPECT_EQ(status_frames, ticks);
}

TEST(Replay, ReportsMalformedLinesWithTheirNumbersAndGoesOn) {
  testing::TempDir d;
  const fs::path log = d.path() / "bad.log", out = d.path() / "out.csv";
  {
    std::ofstream f(log);
    f << "(0000000000.000000) can0 101#0000000000000000\n";
    f << "this is not a frame\n";
    f << "(0000000000.100000) can0 101#00000000000000\n";
  }
  const Outcome r = run(LPTN_BINARY, "replay --quiet --log " + log.string() + " --calibration " + kCalibration.string() +
                                     " --out " + out.string(), d.path());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("bad.log:2: "), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(out));
}

TEST(Replay, BadInputIsOneLineAndWritesNothing) {
  testing::TempDir d;
  const fs::path out = d.path() / "out.csv", garbage = d.path() / "garbage.log";
  std::ofstream(garbage) << "nothing here\n";
  const std::string cases[] = {
      "replay --log " + (d.path() / "missing.log").string() + " --calibration " + kCalibration.string() + " --out " + out.string(),
      "replay --log " + garbage.string() + " --calibration " + kCalibration.string() + " --out " + out.string(),
      "replay --log " + garbage.string() + " --calibration " + garbage.string() + " --out " + out.string(),
      "replay --log " + garbage.string() + " --calibration " + kCalibration.string() + " --out " + out.string() + " --use-actor",
  };
  for (const std::string& args : cases) {
    const Outcome r = run(LPTN_BINARY, args + " --quiet", d.path());
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("lptn: error: "), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << args;
    for (const auto& e : fs::directory_iterator(d.path()))  // no temporary of the output left behind
      EXPECT_EQ(e.path().filename().string().find(".out.csv.tmp-"), std::string::npos) << args;
  }
}

TEST(Daemon, HelpBadArgumentsAndAHostWithoutCan) {
  testing::TempDir d;
  EXPECT_EQ(run(LPTN_DAEMON, "--help", d.path()).code, 0);
  const Outcome none = run(LPTN_DAEMON, "", d.path());
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("exactly one of"), std::string::npos);
  EXPECT_EQ(run(LPTN_DAEMON, "--interface vcan0 --time-scale -1", d.path()).code, 2);
  EXPECT_EQ(run(LPTN_DAEMON, "--replay x --bogus", d.path()).code, 2);
  // This host's kernel has no CAN (or no such interface): a runtime failure, said in one line.
  const Outcome can = run(LPTN_DAEMON, "--interface lptn-no-such-can0", d.path());
  EXPECT_EQ(can.code, 1);
  EXPECT_NE(can.err.find("lptn-no-such-can0"), std::string::npos) << can.err;
}

}  // namespace
}  // namespace lptn::replay
