// `lptn replay` and `lptn convert` on candump, ASC, BLF and MDF4 logs, lptn's own and python-can's: the
// same frames give the same estimates and the same CSV whatever the format; a file in no format is
// one error line; a flood of malformed lines is ten messages and a count.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "lptn_testing/run_lptn.hpp"
#include "lptn_testing/temp_dir.hpp"

namespace lptn::canfile {
namespace {

namespace fs = std::filesystem;
using testing::run;
using testing::slurp;
using testing::TempDir;

std::size_t count_lines(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

class FormatsCli : public ::testing::Test {
 protected:
  // Six minutes of one generated cycle, as a candump log and in lptn's own ASC, BLF and MDF4.
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    const fs::path d = dir_->path();
    const auto g = testing::generate_cycle(d, 7, 6, 6);
    ASSERT_EQ(g.generate.code, 0) << g.generate.err;
    ASSERT_FALSE(g.csv.empty());
    csv_ = g.csv;
    for (const char* name : {"lptn.log", "lptn.asc", "lptn.blf", "lptn.mf4"}) {
      const auto c = run("convert --in " + csv_.string() + " --out " + (d / name).string() + " --start-time 1700000000", d);
      ASSERT_EQ(c.code, 0) << c.err;
    }
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path path(const std::string& name) { return dir_->path() / name; }

  // python-can's conversion of lptn.log into `name` (its format by extension).
  static fs::path python_log(const std::string& name) {
    const std::string cmd = "/usr/bin/python3 " LPTN_PYTHON_CAN_LOGS " convert " + path("lptn.log").string() + " " +
                            path(name).string() + " 2>" + path("python.err").string();
    EXPECT_EQ(std::system(cmd.c_str()), 0) << slurp(path("python.err")) << "(scripts/setup.sh installs python3-can)";
    return path(name);
  }

  static testing::Result replay(const fs::path& log, const fs::path& out) {
    return run("replay --quiet --log " + log.string() + " --calibration " LPTN_DEFAULT_CALIBRATION " --out " + out.string(),
               dir_->path());
  }

  static TempDir* dir_;
  static fs::path csv_;
};
TempDir* FormatsCli::dir_ = nullptr;
fs::path FormatsCli::csv_;

TEST_F(FormatsCli, TheSameFramesGiveTheSameEstimatesWhateverTheFormat) {
  const auto ref = replay(path("lptn.log"), path("est-candump.csv"));
  ASSERT_EQ(ref.code, 0) << ref.err;
  EXPECT_NE(ref.out.find("(candump)"), std::string::npos) << ref.out;
  const std::string expected = slurp(path("est-candump.csv"));
  ASSERT_GT(count_lines(expected), 3000u);  // six minutes at 0.1 s
  for (const auto& [log, format] : std::vector<std::pair<fs::path, std::string>>{
           {path("lptn.asc"), "asc"},
           {path("lptn.blf"), "blf"},
           {path("lptn.mf4"), "mdf4"},
           {python_log("python.asc"), "asc"},
           {python_log("python.blf"), "blf"}}) {
    const fs::path out = path("est-" + log.filename().string() + ".csv");
    const auto r = replay(log, out);
    ASSERT_EQ(r.code, 0) << log << ": " << r.err;
    EXPECT_EQ(r.err, "") << log;
    EXPECT_NE(r.out.find("(" + format + ")"), std::string::npos) << r.out;
    EXPECT_TRUE(slurp(out) == expected) << log << " gives other estimates than the candump log";
  }
}

TEST_F(FormatsCli, EveryFormatConvertsBackToTheSameCsv) {
  const auto ref = run("convert --in " + path("lptn.log").string() + " --out " + path("back-candump.csv").string(), dir_->path());
  ASSERT_EQ(ref.code, 0) << ref.err;
  const std::string expected = slurp(path("back-candump.csv"));
  ASSERT_GT(count_lines(expected), 3000u);
  for (const fs::path& log : {path("lptn.asc"), path("lptn.blf"), path("lptn.mf4"), python_log("py2.asc"), python_log("py2.blf")}) {
    const fs::path out = path("back-" + log.filename().string() + ".csv");
    const auto r = run("convert --in " + log.string() + " --out " + out.string(), dir_->path());
    ASSERT_EQ(r.code, 0) << log << ": " << r.err;
    EXPECT_TRUE(slurp(out) == expected) << log << " converts to another CSV than the candump log";
  }
}

TEST_F(FormatsCli, AFileInNoFormatIsOneErrorLineAndNothingIsWritten) {
  std::mt19937 rng(5);
  std::string junk(200000, '\0');
  for (char& c : junk) c = static_cast<char>(rng());
  std::ofstream(path("junk.bin"), std::ios::binary) << junk;
  const auto r = replay(path("junk.bin"), path("junk-est.csv"));
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(count_lines(r.err), 1u) << r.err.substr(0, 2000);
  EXPECT_NE(r.err.find("junk.bin: not a CAN log lptn reads"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("junk-est.csv")));
  const auto c = run("convert --in " + path("junk.bin").string() + " --format blf --out " + path("junk.csv").string(),
                     dir_->path());
  EXPECT_EQ(c.code, 2);
  EXPECT_EQ(count_lines(c.err), 1u) << c.err.substr(0, 2000);
  EXPECT_NE(c.err.find("not a BLF file"), std::string::npos) << c.err;
  EXPECT_FALSE(fs::exists(path("junk.csv")));
}

TEST_F(FormatsCli, AFloodOfMalformedLinesIsTenMessagesAndACount) {
  std::string flood;
  for (int k = 0; k < 30; ++k) flood += "(1700000000.000000) can0 not-a-frame\n";
  std::ofstream(path("flood.log")) << flood << slurp(path("lptn.log"));
  const auto r = replay(path("flood.log"), path("flood-est.csv"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(count_lines(r.err), 11u) << r.err;
  EXPECT_NE(r.err.find("flood.log:10: "), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("flood.log:11: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("flood.log: 20 more malformed lines skipped"), std::string::npos) << r.err;
}

// A log of two buses, the second carrying the converter's ids with other values (a second
// converter): read as one they would mix; --channel takes one, and says when the asked one is absent.
TEST_F(FormatsCli, ALogOfTwoBusesIsReadOneChannelAtATime) {
  std::ifstream in(path("lptn.asc"));
  std::string two;
  for (std::string line; std::getline(in, line);) {
    two += line + "\n";
    const std::size_t at = line.find(" 1  101 ");  // TC_Electrical on channel 1: a copy on channel 2
    if (at == std::string::npos) continue;
    std::string copy = line;
    copy.replace(at, 8, " 2  101 ");
    copy.replace(copy.size() - 2, 2, "7F");  // another alive counter and pulses: other values
    two += copy + "\n";
  }
  std::ofstream(path("two.asc")) << two;
  const auto ref = replay(path("lptn.asc"), path("est-one-bus.csv"));
  ASSERT_EQ(ref.code, 0) << ref.err;

  const auto mixed = replay(path("two.asc"), path("est-mixed.csv"));
  ASSERT_EQ(mixed.code, 0) << mixed.err;
  EXPECT_NE(mixed.err.find("two.asc: frames of channels 1, 2 read as one bus; --channel picks one"), std::string::npos)
      << mixed.err;

  const auto one = run("replay --quiet --channel 1 --log " + path("two.asc").string() + " --calibration " +
                           LPTN_DEFAULT_CALIBRATION " --out " + path("est-channel-1.csv").string(), dir_->path());
  ASSERT_EQ(one.code, 0) << one.err;
  EXPECT_EQ(one.err, "");
  EXPECT_TRUE(slurp(path("est-channel-1.csv")) == slurp(path("est-one-bus.csv")));

  const auto absent = run("convert --channel 3 --in " + path("two.asc").string() + " --out " + path("two.csv").string(),
                          dir_->path());
  EXPECT_EQ(absent.code, 2);
  EXPECT_EQ(count_lines(absent.err), 1u) << absent.err;
  EXPECT_NE(absent.err.find("two.asc: no frame on channel 3 (the log's channels: 1, 2)"), std::string::npos) << absent.err;
  EXPECT_FALSE(fs::exists(path("two.csv")));
}

// An MDF4 file with a zipped block damaged: one message naming the file and the block's offset,
// the other blocks' frames replayed; junk named *.mf4: one error line, nothing written.
TEST_F(FormatsCli, ADamagedMdf4BlockIsOneMessageWithItsOffsetAndJunkNamedMf4IsRefused) {
  std::string bytes = slurp(path("lptn.mf4"));
  const std::size_t second = bytes.find("##DZ", bytes.find("##DZ") + 1);
  ASSERT_NE(second, std::string::npos) << "lptn.mf4 has fewer than two DZ blocks";
  for (std::size_t i = second + 60; i < second + 90; ++i) bytes[i] = static_cast<char>(~bytes[i]);
  std::ofstream(path("damaged.mf4"), std::ios::binary) << bytes;
  const auto r = replay(path("damaged.mf4"), path("est-damaged.csv"));
  ASSERT_EQ(r.code, 0) << r.err;
  // Then the replay's own warning of inputs that do not fit (frames are missing for a while).
  const std::string first_line = r.err.substr(0, r.err.find('\n') + 1);
  EXPECT_EQ(first_line, path("damaged.mf4").string() + ": byte " + std::to_string(second) +
                       ": data block: zipped data does not inflate to its stated length (corrupt); its records are not "
                       "read (record skipped)\n");
  EXPECT_EQ(r.err.find("damaged.mf4: byte", first_line.size()), std::string::npos) << r.err;
  const auto whole = replay(path("lptn.mf4"), path("est-whole-mf4.csv"));
  ASSERT_EQ(whole.code, 0) << whole.err;
  EXPECT_GT(count_lines(slurp(path("est-damaged.csv"))), 3000u);
  EXPECT_FALSE(slurp(path("est-damaged.csv")) == slurp(path("est-whole-mf4.csv")));

  std::ofstream(path("junk.mf4"), std::ios::binary) << std::string(5000, 'j');
  const auto j = replay(path("junk.mf4"), path("junk-mf4.csv"));
  EXPECT_EQ(j.code, 2);
  EXPECT_EQ(count_lines(j.err), 1u) << j.err;
  EXPECT_NE(j.err.find("junk.mf4: not an MDF4 file"), std::string::npos) << j.err;
  EXPECT_FALSE(fs::exists(path("junk-mf4.csv")));
  const auto c = run("convert --in " + path("junk.mf4").string() + " --out " + path("junk-mf4-back.csv").string(),
                     dir_->path());
  EXPECT_EQ(c.code, 2);
  EXPECT_EQ(count_lines(c.err), 1u) << c.err;
  EXPECT_FALSE(fs::exists(path("junk-mf4-back.csv")));
}

}  // namespace
}  // namespace lptn::canfile
