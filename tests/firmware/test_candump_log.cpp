// The candump -L line format: what canplayer plays and candump writes, read and written exactly.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "lptn/firmware/candump_line.hpp"

namespace lptn::fw {
namespace {

CandumpRecord parse_ok(const char* line) {
  CandumpRecord r;
  const char* why = parse_candump_line(line, r);
  EXPECT_EQ(why, nullptr) << line << ": " << (why ? why : "");
  return r;
}

std::string format(TimeUs t, const char* iface, const CanFrame& f) {
  char buf[200];
  const std::size_t n = format_candump_line(buf, sizeof buf, t, iface, f);
  return std::string(buf, n);
}

TEST(CandumpLog, ReadsAClassicFrameExactly) {
  const CandumpRecord r = parse_ok("(1700000000.123456) vcan0 101#0A1B2C3D00000005");
  EXPECT_EQ(r.time_us, 1700000000123456LL);
  EXPECT_EQ(r.interface, "vcan0");
  EXPECT_EQ(r.frame.id, 0x101u);
  EXPECT_FALSE(r.frame.extended);
  ASSERT_EQ(r.frame.len, 8);
  const std::uint8_t expected[8] = {0x0A, 0x1B, 0x2C, 0x3D, 0, 0, 0, 5};
  EXPECT_EQ(std::memcmp(r.frame.data, expected, 8), 0);
}

TEST(CandumpLog, ReadsExtendedRemoteErrorAndFdFrames) {
  const CandumpRecord ext = parse_ok("(0000000001.000000) can0 18FEF100#01");
  EXPECT_TRUE(ext.frame.extended);
  EXPECT_EQ(ext.frame.id, 0x18FEF100u);
  const CandumpRecord remote = parse_ok("(0000000001.000000) can0 101#R");
  EXPECT_TRUE(remote.frame.remote);
  EXPECT_EQ(remote.frame.len, 0);
  EXPECT_EQ(parse_ok("(0000000001.000000) can0 101#R8").frame.len, 8);
  const CandumpRecord error = parse_ok("(0000000001.000000) can0 20000080#0000000000000000");
  EXPECT_TRUE(error.frame.error);
  const CandumpRecord fd = parse_ok("(0000000001.000000) can0 123##1AABBCCDDEEFF00112233");
  EXPECT_TRUE(fd.frame.fd);
  EXPECT_EQ(fd.frame.len, 10);
  EXPECT_EQ(parse_ok("(0000000001.000000) can0 123#\r").frame.len, 0) << "CRLF and an empty frame";
}

// Newer can-utils and python-can end a line with the frame's direction.
TEST(CandumpLog, ReadsTheDirectionNewerLogsEndWith) {
  const CandumpRecord rx = parse_ok("(1700000000.123456) vcan0 101#0102 R");
  EXPECT_EQ(rx.frame.len, 2);
  EXPECT_EQ(rx.frame.data[1], 2);
  EXPECT_EQ(parse_ok("(1700000000.123456) vcan0 123##00011 T").frame.len, 2);
  EXPECT_TRUE(parse_ok("(1700000000.123456) vcan0 101#R R").frame.remote);
  CandumpRecord r;
  EXPECT_NE(parse_candump_line("(1700000000.123456) vcan0 101#0102 X", r), nullptr);
  EXPECT_NE(parse_candump_line("(1700000000.123456) vcan0 101#0102 RR", r), nullptr);
}

TEST(CandumpLog, NamesWhatIsWrongWithABadLine) {
  const char* bad[] = {
      "",
      "1700000000.123456 can0 101#00",
      "(1700000000.12345) can0 101#00",
      "(17000000x0.123456) can0 101#00",
      "(1700000000.123456)can0 101#00",
      "(1700000000.123456) can0",
      "(1700000000.123456) can0 10100",
      "(1700000000.123456) can0 1010#00",
      "(1700000000.123456) can0 80A#00",
      "(1700000000.123456) can0 1G1#00",
      "(1700000000.123456) can0 101#0",
      "(1700000000.123456) can0 101#001122334455667788",
      "(1700000000.123456) can0 101#ZZ",
      "(1700000000.123456) can0 101#R9",
      "(1700000000.123456) can0 101##",
  };
  for (const char* line : bad) {
    CandumpRecord r;
    const char* why = parse_candump_line(line, r);
    ASSERT_NE(why, nullptr) << "accepted: '" << line << "'";
    EXPECT_GT(std::strlen(why), 10u);
  }
}

TEST(CandumpLog, WritesWhatItReads) {
  const char* lines[] = {
      "(1700000000.123456) vcan0 101#0A1B2C3D00000005",
      "(0000000003.000001) can0 18FEF100#01",
      "(0000000003.000001) can0 101#R",
      "(0000000003.000001) can0 101#R8",
      "(0000000003.000001) can0 20000080#0000000000000000",
      "(0000000003.000001) can0 200#",
  };
  for (const char* line : lines) {
    const CandumpRecord r = parse_ok(line);
    EXPECT_EQ(format(r.time_us, std::string(r.interface).c_str(), r.frame), line);
  }
  char tiny[10];
  EXPECT_EQ(format_candump_line(tiny, sizeof tiny, 0, "can0", CanFrame{}), 0u) << "too small a buffer";
}

}  // namespace
}  // namespace lptn::fw
