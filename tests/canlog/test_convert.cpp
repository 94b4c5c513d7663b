// lptn convert as a user runs it: fleet-dump CSV -> candump log -> CSV, byte-exact frames from a
// hand-written cycle, the log's schedule and alive counters, and what a damaged log gives.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "lptn_testing/run_lptn.hpp"
#include "lptn_testing/temp_dir.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn::canlog {
namespace {

namespace fs = std::filesystem;
using data::Channel;
using testing::Result;
using testing::run;

using testing::slurp;

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

int count_lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

// One frame of a log as this test reads it, independently of the parser under test.
struct Frame {
  long long time_us;
  unsigned id;
  std::string data;  // hex
  int alive() const { return std::stoi(data.substr(14, 1), nullptr, 16); }  // high nibble of byte 7
};

std::vector<Frame> frames_of(const std::string& log) {
  std::vector<Frame> frames;
  for (const std::string& line : lines_of(log)) {
    long long sec = 0, usec = 0;
    char id[9] = {}, data[17] = {};
    EXPECT_EQ(std::sscanf(line.c_str(), "(%lld.%lld) can0 %8[0-9A-F]#%16[0-9A-F]", &sec, &usec, id, data), 4) << line;
    frames.push_back({sec * 1000000 + usec, static_cast<unsigned>(std::stoul(id, nullptr, 16)), data});
  }
  return frames;
}

// A generated cycle (10 minutes) and its conversion, shared by the tests that need real data.
class GeneratedCycle : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir;
    const Result g = run("generate --out " + fleet().string() + " --cycles 2 --seed 3 --minutes-min 10 --minutes-max 10",
                         dir_->path());
    ASSERT_EQ(g.code, 0) << g.err;
    const Result c = run("convert --in " + csv().string() + " --out " + log().string(), dir_->path());
    ASSERT_EQ(c.code, 0) << c.err;
  }
  static void TearDownTestSuite() { delete dir_; }

  static fs::path fleet() { return dir_->path() / "fleet"; }
  static fs::path csv() { return fleet() / "cycle_01_suburban.csv"; }
  static fs::path log() { return dir_->path() / "cycle_01.log"; }
  static const fs::path& scratch() { return dir_->path(); }

 private:
  static inline testing::TempDir* dir_ = nullptr;
};

// CSV -> log -> CSV -> load gives back the original grid within each signal's resolution. Where a
// message goes out `phase` after its grid point, the reloaded value at a grid point lies between
// two frames' values, so it may differ by phase/period of the change between them as well:
//   reloaded(g) = (1 - a) D[g] + a D[g - n],  a = phase / (n * 0.1 s),  |D - G| <= factor / 2
//   => |reloaded(g) - G[g]| <= factor / 2 + a |G[g] - G[g - n]|
// The 1000 ms messages carry every tenth grid point only, so the property holds at those.
TEST_F(GeneratedCycle, RoundTripGivesTheGridBackWithinResolution) {
  const fs::path back = scratch() / "round_trip.csv";
  const Result r = run("convert --in " + log().string() + " --out " + back.string(), scratch());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;  // a clean log: nothing skipped, nothing dropped

  const data::Dataset original = data::load_cycle_file(csv());
  const data::Dataset reloaded = data::load_cycle_file(back);
  ASSERT_EQ(original.cycles.size(), 1u);
  ASSERT_EQ(reloaded.cycles.size(), 1u);
  const data::Cycle& g = original.cycles[0];
  const data::Cycle& b = reloaded.cycles[0];
  // The log starts at the original's first grid point; the reload loses the first point and at
  // most the last stride's points (the 1 Hz airflow frames bracket what the loader keeps).
  const auto offset = static_cast<std::size_t>(std::llround(b.t0_s / 0.1));
  EXPECT_LE(offset, 1u);
  EXPECT_GE(b.steps + offset + 10, g.steps);

  struct Signal {
    Channel channel;
    double factor;  // lptn.dbc
    double phase_s;
    std::size_t stride;
  };
  const Signal signals[] = {
      {Channel::speed_rpm, 0.5, 0, 1},           {Channel::frequency_hz, 0.01, 0, 1},
      {Channel::current_a, 0.05, 0, 1},          {Channel::torque_nm, 0.5, 0.002, 1},
      {Channel::voltage_v, 0.1, 0.004, 1},       {Channel::airflow_m3s, 0.0005, 0.006, 10},
      {Channel::ambient_c, 0.01, 0.006, 10},     {Channel::stator_winding_c, 0.01, 0.008, 10},
      {Channel::rotor_c, 0.01, 0.009, 10},
  };
  for (const Signal& s : signals) {
    const double a = s.phase_s / (static_cast<double>(s.stride) * 0.1);
    std::size_t compared = 0;
    for (std::size_t k = offset; k < b.steps + offset && k < g.steps; ++k) {
      if (k % s.stride != 0 || k < s.stride) continue;
      const double want = g.at(s.channel, k), before = g.at(s.channel, k - s.stride);
      if (std::isnan(want) || std::isnan(before)) continue;  // no frame there or none to interpolate from
      const double got = b.at(s.channel, k - offset);
      const double float_eps = 1e-6 * std::max(1.0, std::fabs(want));  // the loader keeps floats
      const double tolerance = s.factor / 2 + a * std::fabs(want - before) + float_eps;
      ASSERT_LE(std::fabs(got - want), tolerance)
          << data::channel_name(s.channel) << " at t=" << g.time_s(k) << ": " << want << " came back as " << got;
      ++compared;
    }
    EXPECT_GT(compared, g.steps / s.stride - 20) << data::channel_name(s.channel);
  }
}

// lptn inspect --log: an MDF4 log decoded and checked as the CSV converted back from it is
// (the same report but for the file's name), the decoding's frame count said first.
TEST_F(GeneratedCycle, InspectReadsALogAsTheCsvConvertedFromIt) {
  const fs::path mf4 = scratch() / "inspect_me.mf4", back = scratch() / "inspect_me.csv";
  ASSERT_EQ(run("convert --in " + log().string() + " --out " + mf4.string(), scratch()).code, 0);
  ASSERT_EQ(run("convert --in " + mf4.string() + " --out " + back.string(), scratch()).code, 0);
  // The log as MDF4 and back as candump: the very frames (log -> log, nothing decoded).
  const fs::path again = scratch() / "inspect_me_again.log";
  ASSERT_EQ(run("convert --in " + mf4.string() + " --out " + again.string(), scratch()).code, 0);
  EXPECT_EQ(testing::slurp(again), testing::slurp(log()));
  const Result from_log = run("inspect --log " + mf4.string() + " --json", scratch());
  ASSERT_EQ(from_log.code, 0) << from_log.err;
  const Result from_csv = run("inspect --data " + back.string() + " --json", scratch());
  ASSERT_EQ(from_csv.code, 0) << from_csv.err;
  const nlohmann::json a = nlohmann::json::parse(from_log.out), b = nlohmann::json::parse(from_csv.out);
  ASSERT_EQ(a.at("cycles").size(), 1u);
  EXPECT_EQ(a.at("cycles")[0].at("channels"), b.at("cycles")[0].at("channels"));
  EXPECT_EQ(a.at("cycles")[0].at("segments").size(), b.at("cycles")[0].at("segments").size());
  EXPECT_NE(a.at("cycles")[0].at("findings")[0].at("message").get<std::string>().find(" frames decoded over "),
            std::string::npos);
  // Not a log: bad input, one line.
  const Result bad = run("inspect --log " + csv().string() + " --format mdf4", scratch());
  EXPECT_EQ(bad.code, 2);
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
}

TEST_F(GeneratedCycle, EveryMessageAtItsCycleTimeWithAnUnbrokenAliveCounter) {
  const std::vector<Frame> frames = frames_of(slurp(log()));
  ASSERT_FALSE(frames.empty());
  EXPECT_TRUE(std::is_sorted(frames.begin(), frames.end(),
                             [](const Frame& x, const Frame& y) { return x.time_us < y.time_us; }));
  std::map<unsigned, std::vector<Frame>> by_id;
  for (const Frame& f : frames) by_id[f.id].push_back(f);
  const std::map<unsigned, long long> period_us = {{0x101, 100000}, {0x102, 100000}, {0x103, 100000},
                                                   {0x120, 1000000}, {0x130, 1000000}, {0x131, 1000000}};
  ASSERT_EQ(by_id.size(), period_us.size());
  for (const auto& [id, list] : by_id) {
    ASSERT_TRUE(period_us.count(id)) << std::hex << id;
    for (std::size_t i = 0; i < list.size(); ++i) {
      ASSERT_EQ(list[i].alive(), static_cast<int>(i % 16)) << std::hex << id << std::dec << " frame " << i;
      if (i > 0) {
        ASSERT_EQ(list[i].time_us - list[i - 1].time_us, period_us.at(id)) << std::hex << id;
      }
    }
  }
  // The 1000 ms messages at a tenth of the rate: the cycle's points 0, 10, 20, ... of n points.
  // (The generated rotor sensor reads at x.5 s, so its channel starts and ends half a second
  // inside the cycle and its message one frame late and one early at most.)
  const std::size_t fast = by_id[0x101].size();
  for (unsigned id : {0x120u, 0x130u}) EXPECT_EQ(by_id[id].size(), (fast + 9) / 10) << std::hex << id;
  EXPECT_GE(by_id[0x131].size() + 2, (fast + 9) / 10);
  for (unsigned id : {0x102u, 0x103u}) EXPECT_EQ(by_id[id].size(), fast) << std::hex << id;
  // Phases: 0x101 on the grid, the others 2/4/6/8/9 ms after their grid point.
  const long long t0 = by_id[0x101][0].time_us;
  const std::map<unsigned, long long> phase_us = {{0x101, 0},    {0x102, 2000}, {0x103, 4000},
                                                  {0x120, 6000}, {0x130, 8000}, {0x131, 9000}};
  for (const auto& [id, phase] : phase_us)
    for (const Frame& f : by_id[id]) ASSERT_EQ((f.time_us - t0) % period_us.at(id), phase) << std::hex << id;
}

TEST_F(GeneratedCycle, SameInputSameBytesAndADirectoryConvertsEveryCycle) {
  const fs::path again = scratch() / "again.log";
  ASSERT_EQ(run("convert --in " + csv().string() + " --out " + again.string(), scratch()).code, 0);
  EXPECT_EQ(slurp(again), slurp(log()));

  const fs::path logs = scratch() / "logs";
  const Result r = run("convert --in " + fleet().string() + " --out " + logs.string(), scratch());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(count_lines(r.err), 2);  // one progress line a cycle
  EXPECT_EQ(slurp(logs / "cycle_01_suburban.log"), slurp(log()));
  EXPECT_TRUE(fs::exists(logs / "cycle_02_regional.log"));
  EXPECT_EQ(std::distance(fs::directory_iterator(logs), fs::directory_iterator{}), 2);

  // And back: a directory of logs becomes a directory of CSVs the loader takes.
  const fs::path csvs = scratch() / "csvs";
  const Result b = run("convert --in " + logs.string() + " --out " + csvs.string(), scratch());
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_EQ(data::load_fleet_dump({csvs}).cycles.size(), 2u);
  // Existing output is not replaced without --force.
  const Result again_dir = run("convert --in " + logs.string() + " --out " + csvs.string(), scratch());
  EXPECT_EQ(again_dir.code, 2);
  EXPECT_EQ(count_lines(again_dir.err), 1) << again_dir.err;
  EXPECT_EQ(run("convert --force --in " + logs.string() + " --out " + csvs.string(), scratch()).code, 0);
}

// Three grid points, every column but the rotor on every row.
constexpr const char* kTinyCsv =
    "time_s,speed_rpm,torque_nm,current_a,frequency_hz,voltage_v,airflow_m3s,ambient_c,stator_winding_c\n"
    "0.0,1000,250.5,100.05,34.5,400,1.5,20.25,40.5\n"
    "0.1,1001,-250.5,0.4,34.51,400.1,1.5,20.25,40.5\n"
    "0.2,1001,-250.5,0.4,34.51,400.1,1.5,20.25,40.5\n";

TEST(Convert, FramesOfAHandWrittenCycleByteForByte) {
  testing::TempDir t;
  write(t.path() / "tiny.csv", kTinyCsv);
  const Result r = run("convert --in " + (t.path() / "tiny.csv").string() + " --out " + (t.path() / "tiny.log").string() +
                           " --interface vcan0 --start-time 1700000000",
                       t.path());
  ASSERT_EQ(r.code, 0) << r.err;
  // Little-endian raw values, alive counter in the high nibble of byte 7:
  //   t=0.0  0x101: speed 1000/0.5 = 2000 = 07D0, frequency 34.5/0.01 = 3450 = 0D7A,
  //                 current 100.05/0.05 = 2001 = 07D1, pulses 1 (100.05 A > 0.5 A), alive 0
  //          0x102 (+2 ms): torque 250.5/0.5 = 501 = 01F5
  //          0x103 (+4 ms): voltage 400/0.1 = 4000 = 0FA0
  //          0x120 (+6 ms): airflow 1.5/0.0005 = 3000 = 0BB8, ambient 20.25/0.01 = 2025 = 07E9
  //          0x130 (+8 ms): stator 40.5/0.01 = 4050 = 0FD2; no rotor column: no 0x131
  //   t=0.1  0x101: speed 2002 = 07D2, frequency 34.51/0.01 = 3451 = 0D7B, current 0.4/0.05 = 8,
  //                 pulses 0 (0.4 A), alive 1 -> byte 7 = 10
  //          0x102: torque -250.5/0.5 = -501 = FE0B, alive 1;  0x103: 400.1/0.1 = 4001 = 0FA1, alive 1
  //          (the 1000 ms messages wait for t=1.0)
  const std::vector<std::string> expected = {
      "(1700000000.000000) vcan0 101#D0077A0DD1070100", "(1700000000.002000) vcan0 102#F501000000000000",
      "(1700000000.004000) vcan0 103#A00F000000000000", "(1700000000.006000) vcan0 120#B80BE90700000000",
      "(1700000000.008000) vcan0 130#D20F000000000000", "(1700000000.100000) vcan0 101#D2077B0D08000010",
      "(1700000000.102000) vcan0 102#0BFE000000000010", "(1700000000.104000) vcan0 103#A10F000000000010",
      "(1700000000.200000) vcan0 101#D2077B0D08000020", "(1700000000.202000) vcan0 102#0BFE000000000020",
      "(1700000000.204000) vcan0 103#A10F000000000020",
  };
  EXPECT_EQ(lines_of(slurp(t.path() / "tiny.log")), expected);
  EXPECT_NE(r.out.find("11 frames"), std::string::npos) << r.out;
}

TEST(Convert, AMissingTorqueColumnSendsNoTorqueFramesAndComesBackWithoutIt) {
  testing::TempDir t;
  std::string csv;
  for (const std::string& line : lines_of(kTinyCsv)) {  // drop the third cell (torque_nm) of each line
    const auto a = line.find(',', line.find(',') + 1), b = line.find(',', a + 1);
    csv += line.substr(0, a) + line.substr(b) + "\n";
  }
  write(t.path() / "no_torque.csv", csv);
  ASSERT_EQ(run("convert --in " + (t.path() / "no_torque.csv").string() + " --out " + (t.path() / "a.log").string(),
                t.path()).code, 0);
  const std::string log = slurp(t.path() / "a.log");
  EXPECT_EQ(log.find(" 102#"), std::string::npos) << log;
  EXPECT_NE(log.find(" 101#"), std::string::npos) << log;
  ASSERT_EQ(run("convert --in " + (t.path() / "a.log").string() + " --out " + (t.path() / "back.csv").string(),
                t.path()).code, 0);
  EXPECT_EQ(lines_of(slurp(t.path() / "back.csv"))[0],
            "time_s,speed_rpm,current_a,frequency_hz,voltage_v,airflow_m3s,ambient_c,stator_winding_c");
}

TEST(Convert, AValueOutsideItsSignalsRangeIsBadInputAndWritesNothing) {
  testing::TempDir t;
  std::string csv = kTinyCsv;
  csv.replace(csv.find("0.4,"), 3, "3100");  // line 3: 3100 A, above StatorCurrent's 3000 A
  write(t.path() / "hot.csv", csv);
  const Result r = run("convert --in " + (t.path() / "hot.csv").string() + " --out " + (t.path() / "hot.log").string(), t.path());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  for (const char* must : {"hot.csv:3:", "current_a", "StatorCurrent", "t=0.100"})
    EXPECT_NE(r.err.find(must), std::string::npos) << must << " in " << r.err;
  EXPECT_FALSE(fs::exists(t.path() / "hot.log"));
  for (const auto& entry : fs::directory_iterator(t.path()))
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
}

TEST(Convert, ADamagedLogGivesItsGoodFramesAndSaysWhatItDropped) {
  testing::TempDir t;
  write(t.path() / "damaged.log",
        "(1700000000.000000) can0 101#D0077A0DD1070100\n"            // 1 good
        "this is not a frame\n"                                       // 2 malformed
        "(1700000000.002000) can0 123##1AABB\n"                       // 3 CAN FD
        "(1700000000.004000) can0 101#R\n"                            // 4 remote
        "(1700000000.005000) can0 20000080#0000000000000000\n"        // 5 error frame
        "(1700000000.005500) can0 7FF#0011\n"                         // 6 unknown id
        "(1700000000.006000) can0 120#B80BE90700000000\n"             // 7 good
        "(1700000000.007000) can0 200#0000000000000000\n"             // 8 the estimator's output
        "(1700000000.008000) can0 130#D20F000000000000\n"             // 9 good
        "(1700000000.005000) can0 101#D2077B0D08000010\n"             // 10 back in time
        "(1700000000.100000) can0 101#D2077B0D08000010\n"             // 11 good
        "(1700000000.100000) can0 101#D207\n");                       // 12 wrong length
  const Result r = run("convert --in " + (t.path() / "damaged.log").string() + " --out " + (t.path() / "d.csv").string(),
                       t.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(t.path() / "d.csv"),
            "time_s,speed_rpm,current_a,frequency_hz,airflow_m3s,ambient_c,stator_winding_c\n"
            "0.000000,1000.0,100.05,34.50,,,\n"
            "0.006000,,,,1.5000,20.25,\n"
            "0.008000,,,,,,40.50\n"
            "0.100000,1001.0,0.40,34.51,,,\n");
  for (const char* must : {"damaged.log:2:", "damaged.log:10:", "CAN FD (first on line 3)", "remote frame (first on line 4)",
                           "error frame (first on line 5)", "unknown id (first on line 6)",
                           "estimator output (LPTN_*) (first on line 8)", "wrong length (first on line 12)"})
    EXPECT_NE(r.err.find(must), std::string::npos) << must << " in\n" << r.err;
  EXPECT_EQ(count_lines(r.err), 3) << r.err;  // two dropped lines and one summary
}

TEST(Convert, ALogWithoutFramesOrWithoutARequiredMessageIsBadInput) {
  testing::TempDir t;
  write(t.path() / "empty.log", "garbage\n(1700000000.000000) can0 7FF#00\n");
  const Result none = run("convert --in " + (t.path() / "empty.log").string() + " --out " + (t.path() / "e.csv").string(), t.path());
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("no frame"), std::string::npos) << none.err;
  EXPECT_FALSE(fs::exists(t.path() / "e.csv"));

  write(t.path() / "no_cooling.log",
        "(1700000000.000000) can0 101#D0077A0DD1070100\n(1700000000.008000) can0 130#D20F000000000000\n");
  const Result r = run("convert --in " + (t.path() / "no_cooling.log").string() + " --out " + (t.path() / "n.csv").string(), t.path());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  for (const char* must : {"no_cooling.log", "TC_Cooling", "airflow_m3s"}) EXPECT_NE(r.err.find(must), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(t.path() / "n.csv"));
}

TEST(Convert, HelpNamesBothDirectionsAndTheMessages) {
  testing::TempDir t;
  const Result r = run("convert --help", t.path());
  EXPECT_EQ(r.code, 0);
  for (const char* must : {"--in", "--out", "--interface", "--start-time", "--force", "candump", "TC_Electrical", "0x131"})
    EXPECT_NE(r.out.find(must), std::string::npos) << must;
}

}  // namespace
}  // namespace lptn::canlog
