// lptn's candump, ASC and BLF readers and writers against each other and against python-can
// (Debian's python3-can), an implementation this project did not write: frames lptn writes,
// python-can reads the same; frames python-can writes, lptn reads the same.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "lptn_testing/temp_dir.hpp"
#include "can/canfile/can_log.hpp"
#include "make_frame.hpp"

namespace lptn::canfile {
namespace {

namespace fs = std::filesystem;
using fw::CanFrame;
using fw::TimeUs;
using testing::TempDir;

struct Stamped {
  TimeUs t;
  CanFrame f;
};

// Every kind of frame a converter's log holds, then enough classic frames (6000, 48 bytes each in
// a BLF) to fill more than two 128 KiB containers, so that objects straddle them.
std::vector<Stamped> sample_frames() {
  const TimeUs t0 = 1700000000LL * fw::kUsPerS + 123456;
  std::vector<Stamped> v;
  v.push_back({t0, make_frame(0x101, false, {0x0A, 0x1B, 0x2C, 0x3D, 0x00, 0x00, 0x00, 0x05})});
  v.push_back({t0 + 250, make_frame(0x18FEF100, true, {1, 2, 3})});
  CanFrame remote = make_frame(0x200, false, {});
  remote.remote = true;
  remote.len = 4;
  v.push_back({t0 + 1000, remote});
  CanFrame error;
  error.error = true;
  error.id = 0x80;  // a bus error: what python-can's candump reader takes for an error frame
  v.push_back({t0 + 2000, error});
  std::vector<std::uint8_t> b64(64);
  for (std::size_t i = 0; i < b64.size(); ++i) b64[i] = static_cast<std::uint8_t>(i * 7);
  v.push_back({t0 + 3123, make_frame(0x123, false, b64, true)});
  v.push_back({t0 + 4000, make_frame(0x1ABCDE0, true, {9, 8, 7, 6, 5, 4, 3, 2, 1, 0, 0xFF, 0xEE}, true)});
  v.push_back({t0 + 5000, make_frame(0x7FF, false, {})});
  for (int k = 0; k < 6000; ++k) {
    const auto b = static_cast<std::uint8_t>(k);
    v.push_back({t0 + 10000 + k * 997, make_frame(0x100 + static_cast<std::uint32_t>(k % 5), false,
                                             {b, static_cast<std::uint8_t>(k >> 8), 0x55, b, 0, 0, 0, 1})});
  }
  return v;
}

// One frame as python_can_logs.py dumps it: an error frame by its flag alone (ASC keeps no id).
std::string canonical(TimeUs since_first, const CanFrame& f) {
  char head[96];
  if (f.error) {
    std::snprintf(head, sizeof head, "%lld.%06lld 0 0 0 1 0 0 ", static_cast<long long>(since_first / fw::kUsPerS),
                  static_cast<long long>(since_first % fw::kUsPerS));
    return head;
  }
  std::snprintf(head, sizeof head, "%lld.%06lld %X %d %d 0 %d %u ", static_cast<long long>(since_first / fw::kUsPerS),
                static_cast<long long>(since_first % fw::kUsPerS), static_cast<unsigned>(f.id), f.extended, f.remote,
                f.fd, static_cast<unsigned>(f.len));
  std::string s = head;
  if (!f.remote)
    for (unsigned i = 0; i < f.len; ++i) {
      char b[4];
      std::snprintf(b, sizeof b, "%02X", f.data[i]);
      s += b;
    }
  return s;
}

std::vector<std::string> canonical(const std::vector<Stamped>& v) {
  std::vector<std::string> out;
  for (const Stamped& s : v) out.push_back(canonical(s.t - v.front().t, s.f));
  return out;
}

void write_bytes(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

fs::path write_log(const fs::path& p, LogFormat format, const std::vector<Stamped>& v) {
  auto w = make_log_writer(format);
  for (const Stamped& s : v) w->add(s.t, s.f);
  write_bytes(p, w->finish());
  return p;
}

struct Read {
  std::vector<Stamped> frames;
  std::vector<std::string> bad;  // "RECORD: why"
};

Read read_log(const fs::path& p, LogFormat format) {
  Read r;
  auto source = open_log(p, format);
  TimeUs t = 0;
  CanFrame f;
  const char* why = nullptr;
  for (frames::FrameSource::Status s; (s = source->next(t, f, why)) != frames::FrameSource::Status::end;) {
    if (s == frames::FrameSource::Status::bad) r.bad.push_back(std::to_string(source->record()) + ": " + why);
    else r.frames.push_back({t, f});
  }
  return r;
}

// Debian's python3 and python3-can, not whatever python3 is first on the PATH.
std::vector<std::string> python_can(const std::string& args, const fs::path& scratch) {
  const fs::path out = scratch / "python.out", err = scratch / "python.err";
  const std::string cmd = "/usr/bin/python3 " LPTN_PYTHON_CAN_LOGS " " + args + " >" + out.string() + " 2>" + err.string();
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd << "\n" << testing::slurp(err) << "(scripts/setup.sh installs python3-can)";
  std::vector<std::string> lines;
  std::ifstream in(out);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

class EveryFormat : public ::testing::TestWithParam<LogFormat> {};

TEST_P(EveryFormat, WhatLptnWritesItReadsBackFrameForFrame) {
  TempDir t;
  const auto frames = sample_frames();
  const Read r = read_log(write_log(t.path() / (std::string("a") + format_extension(GetParam())), GetParam(), frames), GetParam());
  EXPECT_TRUE(r.bad.empty()) << r.bad.front();
  ASSERT_EQ(r.frames.size(), frames.size());
  EXPECT_EQ(canonical(r.frames), canonical(frames));
  // candump and BLF keep the absolute time (BLF: the header's millisecond plus the objects' offsets);
  // ASC counts from its first frame.
  const TimeUs offset = GetParam() == LogFormat::asc ? frames.front().t : 0;
  EXPECT_EQ(r.frames.front().t + offset, frames.front().t);
  EXPECT_EQ(r.frames.back().t + offset, frames.back().t);
}

TEST_P(EveryFormat, WhatLptnWritesPythonCanReadsTheSame) {
  TempDir t;
  const auto frames = sample_frames();
  const fs::path log = write_log(t.path() / (std::string("lptn") + format_extension(GetParam())), GetParam(), frames);
  EXPECT_EQ(python_can("dump " + log.string(), t.path()), canonical(frames));
}

TEST_P(EveryFormat, WhatPythonCanWritesLptnReadsTheSame) {
  TempDir t;
  const auto frames = sample_frames();
  const fs::path candump = write_log(t.path() / "source.log", LogFormat::candump, frames);
  const fs::path log = t.path() / (std::string("python") + format_extension(GetParam()));
  python_can("convert " + candump.string() + " " + log.string(), t.path());
  ASSERT_TRUE(fs::exists(log));
  EXPECT_EQ(detect_format(log), GetParam());
  const Read r = read_log(log, GetParam());
  EXPECT_TRUE(r.bad.empty()) << r.bad.front();
  auto expected = frames;
  // python-can's candump writer writes a remote frame as "200#R", without its length.
  if (GetParam() == LogFormat::candump)
    for (Stamped& s : expected)
      if (s.f.remote) s.f.len = 0;
  EXPECT_EQ(canonical(r.frames), canonical(expected));
}

INSTANTIATE_TEST_SUITE_P(Formats, EveryFormat, ::testing::Values(LogFormat::candump, LogFormat::asc, LogFormat::blf),
                         [](const auto& p) { return std::string(format_name(p.param)); });

TEST(DetectFormat, ByContentWhateverTheNameThenByName) {
  TempDir t;
  const auto frames = sample_frames();
  for (LogFormat f : {LogFormat::candump, LogFormat::asc, LogFormat::blf})
    EXPECT_EQ(detect_format(write_log(t.path() / (std::string("x-") + format_name(f) + ".dat"), f, frames)), f);
  // A damaged candump log: garbage first, then frames. Its content says nothing; its name does.
  std::string damaged = "\x01\x02garbage\n";
  for (int k = 0; k < 12; ++k) damaged += "not a line\n";
  damaged += "(1700000000.000000) can0 101#00\n";
  write_bytes(t.path() / "damaged.log", damaged);
  EXPECT_EQ(detect_format(t.path() / "damaged.log"), LogFormat::candump);
  write_bytes(t.path() / "damaged.dat", damaged);
  try {
    detect_format(t.path() / "damaged.dat");
    ADD_FAILURE() << "a file in no format was given one";
  } catch (const LogError& e) {
    EXPECT_NE(std::string(e.what()).find("damaged.dat: not a CAN log lptn reads"), std::string::npos) << e.what();
  }
  EXPECT_THROW(open_log(t.path() / "damaged.dat", LogFormat::blf), LogError);  // no "LOGG"
}

// A BLF with a container damaged in the middle: that container's objects are lost and reported,
// every other container's frames are read.
TEST(BlfReader, ADamagedContainerIsReportedAndTheRestIsRead) {
  TempDir t;
  const auto frames = sample_frames();
  auto w = make_log_writer(LogFormat::blf);
  for (const Stamped& s : frames) w->add(s.t, s.f);
  std::string bytes = w->finish();
  // The second container: the second "LOBJ" at the top level, after the first container's bytes.
  const std::size_t first = bytes.find("LOBJ");
  const std::uint32_t first_size = static_cast<std::uint8_t>(bytes[first + 8]) |
                                   static_cast<std::uint8_t>(bytes[first + 9]) << 8 |
                                   static_cast<std::uint8_t>(bytes[first + 10]) << 16;
  const std::size_t second = first + first_size + first_size % 4;
  ASSERT_EQ(bytes.substr(second, 4), "LOBJ");
  for (std::size_t i = second + 40; i < second + 60; ++i) bytes[i] = static_cast<char>(~bytes[i]);
  write_bytes(t.path() / "damaged.blf", bytes);
  const Read r = read_log(t.path() / "damaged.blf", LogFormat::blf);
  ASSERT_FALSE(r.bad.empty());
  EXPECT_NE(r.bad.front().find("does not inflate"), std::string::npos) << r.bad.front();
  EXPECT_GT(r.frames.size(), frames.size() / 3);   // the first and third containers
  EXPECT_LT(r.frames.size(), frames.size());
  for (std::size_t i = 1; i < r.frames.size(); ++i) EXPECT_GE(r.frames[i].t, r.frames[i - 1].t);
}

// ASC as CANoe writes it, with what python-can does not write: decimal base, relative time stamps,
// other events, a symbolic name in a CAN FD line, CANoe's trailing fields.
TEST(AscReader, ReadsCanoesVariants) {
  TempDir t;
  write_bytes(t.path() / "canoe.asc",
              "date Mon Nov 23 06:30:55.123 am 2026\n"
              "base dec  timestamps relative\n"
              "no internal events logged\n"
              "// version 13.0.0\n"
              "Begin Triggerblock Mon Nov 23 06:30:55.123 am 2026\n"
              "   0.000000 Start of measurement\n"
              "   0.010000 1  257             Rx   d 8 10 27 44 61 0 0 0 5  Length = 228000 BitCount = 118 ID = 257\n"
              "   0.005000 1 Statistic: D 0 R 0 XD 0 XR 0 E 0 O 0 B 0.00%\n"
              "   0.002500 2  419361024x      Tx   d 3 1 2 3\n"
              "   0.001000 CANFD   1 Rx      291  Speed_Msg                        1 0 9 12 1 2 3 4 5 6 7 8 9 10 11 12"
              "   130000   203 303000 b1000000 00000000 00000000 00000000 00000000\n"
              "   0.001000 1  ErrorFrame\n"
              "End TriggerBlock\n");
  const Read r = read_log(t.path() / "canoe.asc", LogFormat::asc);
  EXPECT_TRUE(r.bad.empty()) << r.bad.front();
  ASSERT_EQ(r.frames.size(), 4u);
  EXPECT_EQ(r.frames[0].t, 10000);
  EXPECT_EQ(canonical(0, r.frames[0].f), "0.000000 101 0 0 0 0 8 0A1B2C3D00000005");
  EXPECT_EQ(r.frames[1].t, 17500);  // the statistics line's 5 ms count too
  EXPECT_EQ(canonical(0, r.frames[1].f), "0.000000 18FEF100 1 0 0 0 3 010203");
  EXPECT_EQ(canonical(0, r.frames[2].f), "0.000000 123 0 0 0 1 12 0102030405060708090A0B0C");
  EXPECT_TRUE(r.frames[3].f.error);
  EXPECT_EQ(r.frames[3].t, 19500);
}

TEST(AscReader, AMalformedFrameLineIsBadWithItsLineNumber) {
  TempDir t;
  write_bytes(t.path() / "bad.asc",
              "base hex  timestamps absolute\n"
              "   0.010000 1  1G1             Rx   d 8 00 00 00 00 00 00 00 00\n"
              "   0.020000 1  101             Rx   d 8 00 00 00\n"
              "   0.030000 1  101             Rx   d 1 00\n"
              "garbage\n");
  const Read r = read_log(t.path() / "bad.asc", LogFormat::asc);
  ASSERT_EQ(r.bad.size(), 3u);
  EXPECT_EQ(r.bad[0], "2: id is not a number of 11 bits (an 'x' marks an extended id)");
  EXPECT_EQ(r.bad[1], "3: fewer data bytes than its length says");
  EXPECT_EQ(r.bad[2], "5: expected a time stamp (seconds) at the start of an ASC event line");
  ASSERT_EQ(r.frames.size(), 1u);
  EXPECT_EQ(r.frames[0].t, 30000);
}

// A classic frame's line is read in one pass (ClassicLine), anything it does not take by the
// general reading: each field malformed in turn gets the general reading's complaint, and lines
// the one pass passes on (tabs, a carriage return, one-digit bytes) are still frames.
TEST(AscReader, EachFieldOfAClassicLineMalformedGetsItsComplaint) {
  TempDir t;
  write_bytes(t.path() / "fields.asc",
              "base hex  timestamps absolute\n"
              "   0.010000 1  101             Rx   d \n"            // no length code, a blank after 'd'
              "   0.020000 1  101234567890    Rx   d 0\n"           // an id of 12 digits
              "   0.030000 1  800             Rx   d 0\n"           // above 7FF
              "   0.040000 1  1ABx            Rx   d 1 100\n"       // a byte of 0x100
              "   1234567890123.000000 1  101 Rx   d 0\n"           // 13 digits of seconds
              "\t0.050000\t1\t1ABx\tTx\tD\t2\t0A\tb\r\n"           // tabs, one digit, '\r'
              "   0.060000 1  101x            Rx   d 1 00\n");
  const Read r = read_log(t.path() / "fields.asc", LogFormat::asc);
  ASSERT_EQ(r.bad.size(), 5u);
  EXPECT_EQ(r.bad[0], "2: data length code is not a hex digit");
  EXPECT_EQ(r.bad[1], "3: id is not a number of 11 bits (an 'x' marks an extended id)");
  EXPECT_EQ(r.bad[2], "4: id is not a number of 11 bits (an 'x' marks an extended id)");
  EXPECT_EQ(r.bad[3], "5: a data byte is not a number from 0 to 255");
  EXPECT_EQ(r.bad[4], "6: expected a time stamp (seconds) at the start of an ASC event line");
  ASSERT_EQ(r.frames.size(), 2u);
  EXPECT_EQ(r.frames[0].t, 50000);
  EXPECT_EQ(canonical(0, r.frames[0].f), "0.000000 1AB 1 0 0 0 2 0A0B");
  EXPECT_EQ(r.frames[1].t, 60000);
  EXPECT_EQ(canonical(0, r.frames[1].f), "0.000000 101 1 0 0 0 1 00");
}

}  // namespace
}  // namespace lptn::canfile
