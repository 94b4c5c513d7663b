// MDF4 bus logging files (can/canfile/mdf4_read.cpp, mdf4_write.cpp): CANedge loggers' files
// (corpus/mdf4, README.md there) frame for frame against their reference frames; what lptn writes
// read back as the candump log of the same frames; files built here block by block for what neither
// has (sorted groups, signal data, DL lists with offsets, plain deflate, 2-byte record ids, several
// data groups); damaged, cut short, and in no format.
#include <gtest/gtest.h>

#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
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

const fs::path kCorpus = LPTN_MDF4_CORPUS;
// Records in each DZ block lptn's writer writes.
constexpr std::size_t kPerBlock = 4096;

struct Stamped {
  TimeUs t;
  CanFrame f;
  std::string channel;
};

struct Read {
  std::vector<Stamped> frames;
  std::vector<std::string> bad;  // record_message's lines
};

Read read_log(const fs::path& p, LogFormat format = LogFormat::mdf4) {
  Read r;
  auto source = open_log(p, format);
  TimeUs t = 0;
  CanFrame f;
  const char* why = nullptr;
  for (frames::FrameSource::Status s; (s = source->next(t, f, why)) != frames::FrameSource::Status::end;) {
    if (s == frames::FrameSource::Status::bad) r.bad.push_back(record_message(p, *source, source->record(), why));
    else r.frames.push_back({t, f, std::string(source->channel())});
  }
  return r;
}

// As corpus/mdf4/decode_mf4.py prints a frame.
std::string line(const Stamped& s) {
  char head[128];
  std::snprintf(head, sizeof head, "%lld.%06lld %s %X %d %d %d %d %u ", static_cast<long long>(s.t / fw::kUsPerS),
                static_cast<long long>(s.t % fw::kUsPerS), s.channel.c_str(), static_cast<unsigned>(s.f.id),
                s.f.extended, s.f.remote, s.f.error, s.f.fd, s.f.error ? 0u : static_cast<unsigned>(s.f.len));
  std::string out = head;
  if (!s.f.remote && !s.f.error)
    for (unsigned i = 0; i < s.f.len; ++i) {
      char b[4];
      std::snprintf(b, sizeof b, "%02X", s.f.data[i]);
      out += b;
    }
  return out;
}

std::vector<std::string> lines(const std::vector<Stamped>& v) {
  std::vector<std::string> out;
  for (const Stamped& s : v) out.push_back(line(s));
  return out;
}

std::vector<std::string> file_lines(const fs::path& p) {
  std::vector<std::string> out;
  std::ifstream in(p);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

std::string slurp_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

// The bytes `writer` makes of `frames`.
std::string written(LogFormat format, const std::vector<Stamped>& frames) {
  auto w = make_log_writer(format);
  for (const Stamped& s : frames) w->add(s.t, s.f);
  return w->finish();
}

// Every kind of frame, then `n` classic frames: 30000 fill eight of the writer's DZ blocks.
std::vector<Stamped> sample_frames(int n = 30000) {
  const TimeUs t0 = 1700000000LL * fw::kUsPerS + 123456;
  std::vector<Stamped> v;
  v.push_back({t0, make_frame(0x101, false, {0x0A, 0x1B, 0x2C, 0x3D, 0x00, 0x00, 0x00, 0x05}), "1"});
  v.push_back({t0 + 250, make_frame(0x18FEF100, true, {1, 2, 3}), "1"});
  CanFrame remote = make_frame(0x200, false, {});
  remote.remote = true;
  remote.len = 4;
  v.push_back({t0 + 1000, remote, "1"});
  CanFrame error;
  error.error = true;
  error.id = 0x80;
  v.push_back({t0 + 2000, error, "1"});
  std::vector<std::uint8_t> b64(64);
  for (std::size_t i = 0; i < b64.size(); ++i) b64[i] = static_cast<std::uint8_t>(i * 7);
  v.push_back({t0 + 3123, make_frame(0x123, false, b64, true), "1"});
  v.push_back({t0 + 4000, make_frame(0x1ABCDE0, true, {9, 8, 7, 6, 5, 4, 3, 2, 1, 0, 0xFF, 0xEE}, true), "1"});
  v.push_back({t0 + 5000, make_frame(0x7FF, false, {}), "1"});
  for (int k = 0; k < n; ++k) {
    const auto b = static_cast<std::uint8_t>(k);
    v.push_back({t0 + 10000 + k * 997LL, make_frame(0x100 + static_cast<std::uint32_t>(k % 5), false,
                                               {b, static_cast<std::uint8_t>(k >> 8), 0x55, b, 0, 0, 0, 1}), "1"});
  }
  return v;
}

// ---------------------------------------------------------------------------------------------
// Files other tools wrote.

class Corpus : public ::testing::TestWithParam<const char*> {};
// The loggers' own (unfinalized) files, whose data block is the file's last block.
class CorpusRaw : public Corpus {};

TEST_P(Corpus, ReadsFrameForFrameAsTheReferenceReading) {
  const fs::path mf4 = kCorpus / (std::string(GetParam()) + ".MF4");
  EXPECT_EQ(detect_format(mf4), LogFormat::mdf4);
  const Read r = read_log(mf4);
  EXPECT_TRUE(r.bad.empty()) << r.bad.front();
  const auto expected = file_lines(kCorpus / (std::string(GetParam()) + ".frames.txt"));
  ASSERT_GT(expected.size(), 1000u);
  EXPECT_EQ(lines(r.frames), expected);
}

// Cut anywhere inside its data: the frames before the cut, then one bad record naming the file and
// the data block's offset.
TEST_P(CorpusRaw, CutShortItReadsTheFramesBeforeTheCutAndReportsOneBadRecord) {
  TempDir t;
  const std::string bytes = slurp_bytes(kCorpus / (std::string(GetParam()) + ".MF4"));
  const auto all = read_log(kCorpus / (std::string(GetParam()) + ".MF4")).frames;
  const fs::path cut = t.path() / "cut.mf4";
  const std::size_t dt = bytes.find("##DT");
  write_bytes(cut, bytes.substr(0, dt + (bytes.size() - dt) * 2 / 3 + 5));
  const Read r = read_log(cut);
  ASSERT_EQ(r.bad.size(), 1u) << r.bad[1];
  EXPECT_EQ(r.bad[0], cut.string() + ": byte " + std::to_string(dt) +
                          ": data block: the file ends inside a record (cut short)");
  EXPECT_GT(r.frames.size(), all.size() / 3);
  EXPECT_LT(r.frames.size(), all.size());
  EXPECT_EQ(lines(r.frames), lines({all.begin(), all.begin() + static_cast<std::ptrdiff_t>(r.frames.size())}));
}

// The logger's id in the file's name ("canedge-FCBF0606-00000001-..."): the test's name.
std::string device_id(const ::testing::TestParamInfo<const char*>& p) {
  const std::string name = p.param;
  return name.substr(name.find("-0000000") - 8, 8);
}

INSTANTIATE_TEST_SUITE_P(CanEdge, Corpus,
                         ::testing::Values("canedge-FCBF0606-00000001-60B621D9", "canedge-2F6913DB-00000002-63BEFDF9",
                                           "canedge-finalized-3BA199E2-00000005-60FEB5A8"),
                         device_id);
INSTANTIATE_TEST_SUITE_P(CanEdge, CorpusRaw,
                         ::testing::Values("canedge-FCBF0606-00000001-60B621D9", "canedge-2F6913DB-00000002-63BEFDF9"),
                         device_id);

TEST(Mdf4Corpus, ConvertedToCandumpItIsTheCandumpLogOfTheReferenceFrames) {
  const Read r = read_log(kCorpus / "canedge-FCBF0606-00000001-60B621D9.MF4");
  // The reference frames, parsed back, written as candump.
  std::vector<Stamped> reference;
  for (const std::string& l : file_lines(kCorpus / "canedge-FCBF0606-00000001-60B621D9.frames.txt")) {
    long long s, us;
    char channel[16], data[200] = "";
    unsigned id, ext, rtr, err, fd, len;
    ASSERT_GE(std::sscanf(l.c_str(), "%lld.%lld %15s %X %u %u %u %u %u %199s", &s, &us, channel, &id, &ext, &rtr, &err,
                          &fd, &len, data),
              9)
        << l;
    CanFrame f;
    f.id = id;
    f.extended = ext;
    f.remote = rtr;
    f.error = err;
    f.fd = fd;
    f.len = static_cast<std::uint8_t>(len);
    for (unsigned i = 0; i < len && data[2 * i]; ++i) {
      unsigned b;
      std::sscanf(data + 2 * i, "%2X", &b);
      f.data[i] = static_cast<std::uint8_t>(b);
    }
    reference.push_back({s * fw::kUsPerS + us, f, channel});
  }
  ASSERT_EQ(reference.size(), 1815u);
  EXPECT_EQ(written(LogFormat::candump, r.frames), written(LogFormat::candump, reference));
}

// ---------------------------------------------------------------------------------------------
// What lptn writes.

TEST(Mdf4Writer, WhatItWritesReadsBackAsTheCandumpLogOfTheSameFrames) {
  TempDir t;
  const auto frames = sample_frames();
  const std::string mdf = written(LogFormat::mdf4, frames);
  EXPECT_EQ(mdf.substr(0, 16), "MDF     4.10    ");
  const fs::path p = t.path() / "a.dat";  // detected by content, not name
  write_bytes(p, mdf);
  EXPECT_EQ(detect_format(p), LogFormat::mdf4);
  const Read r = read_log(p);
  EXPECT_TRUE(r.bad.empty()) << r.bad.front();
  ASSERT_EQ(r.frames.size(), frames.size());
  EXPECT_EQ(lines(r.frames), lines(frames));
  EXPECT_EQ(written(LogFormat::candump, r.frames), written(LogFormat::candump, frames));
  // And ASC (time stamps from the first frame, as ASC keeps them) of the frames read back is ASC of
  // the frames written.
  EXPECT_EQ(written(LogFormat::asc, r.frames), written(LogFormat::asc, frames));
  // Eight DZ blocks (kPerBlock records each at most), transposed then deflated, under a DL and an HL.
  std::size_t dz = 0;
  for (std::size_t at = 0; (at = mdf.find("##DZ", at)) != std::string::npos; ++at) ++dz;
  EXPECT_EQ(dz, 8u);
  EXPECT_NE(mdf.find("##HL"), std::string::npos);
  EXPECT_NE(mdf.find("##DL"), std::string::npos);
  EXPECT_LT(mdf.size(), frames.size() * 81 / 4);  // compressed
}

TEST(Mdf4Writer, NoFramesIsAFileOfNoFrames) {
  TempDir t;
  write_bytes(t.path() / "empty.mf4", written(LogFormat::mdf4, {}));
  const Read r = read_log(t.path() / "empty.mf4");
  EXPECT_TRUE(r.bad.empty());
  EXPECT_TRUE(r.frames.empty());
}

// The offset of the n-th (0-based) block of this id ("##DZ").
std::size_t nth(const std::string& bytes, const char* id, int n) {
  std::size_t at = 0;
  for (int k = 0; k <= n; ++k, ++at)
    if ((at = bytes.find(id, at)) == std::string::npos) return at;
  return at - 1;
}

TEST(Mdf4Reader, ACorruptDzBlockIsOneBadRecordNamingItsOffsetAndTheOthersAreRead) {
  TempDir t;
  const auto frames = sample_frames();
  std::string bytes = written(LogFormat::mdf4, frames);
  const std::size_t second = nth(bytes, "##DZ", 1);
  ASSERT_NE(second, std::string::npos);
  for (std::size_t i = second + 60; i < second + 90; ++i) bytes[i] = static_cast<char>(~bytes[i]);
  const fs::path p = t.path() / "corrupt.mf4";
  write_bytes(p, bytes);
  const Read r = read_log(p);
  ASSERT_EQ(r.bad.size(), 1u);
  EXPECT_EQ(r.bad[0], p.string() + ": byte " + std::to_string(second) +
                          ": data block: zipped data does not inflate to its stated length (corrupt); its records are "
                          "not read");
  // The other blocks' frames, all of them.
  ASSERT_EQ(r.frames.size(), frames.size() - kPerBlock);
  const auto block = static_cast<std::ptrdiff_t>(kPerBlock);
  std::vector<Stamped> expected(frames.begin(), frames.begin() + block);
  expected.insert(expected.end(), frames.begin() + 2 * block, frames.end());
  EXPECT_EQ(lines(r.frames), lines(expected));
}

// Cut inside the third of eight DZ blocks: one message for it and the five after the file's end;
// the first two blocks' frames.
TEST(Mdf4Reader, CutInsideADzBlockItReportsThatBlockOnceAndReadsTheBlocksBefore) {
  TempDir t;
  const auto frames = sample_frames();
  const std::string bytes = written(LogFormat::mdf4, frames);
  const std::size_t third = nth(bytes, "##DZ", 2);  // of eight: the rest is cut too
  ASSERT_NE(third, std::string::npos);
  const fs::path p = t.path() / "cut.mf4";
  write_bytes(p, bytes.substr(0, third + 200));
  const Read r = read_log(p);
  ASSERT_EQ(r.bad.size(), 1u);
  EXPECT_EQ(r.bad[0], p.string() + ": byte " + std::to_string(third) +
                          ": data block: the file ends inside the block (cut short); its records are not read, nor "
                          "those of the 5 data blocks after the file's end");
  ASSERT_EQ(r.frames.size(), 2u * kPerBlock);
  EXPECT_EQ(lines(r.frames), lines({frames.begin(), frames.begin() + 2 * static_cast<std::ptrdiff_t>(kPerBlock)}));
}

TEST(Mdf4Reader, AFileInNoFormatOrAnotherMdfVersionIsRefusedAsAWhole) {
  TempDir t;
  write_bytes(t.path() / "junk.mf4", std::string(4096, '\x5A'));
  try {
    open_log(t.path() / "junk.mf4", LogFormat::mdf4);
    ADD_FAILURE() << "junk read as MDF4";
  } catch (const LogError& e) {
    EXPECT_EQ(std::string(e.what()), (t.path() / "junk.mf4").string() +
                                         ": not an MDF4 file (it does not start with an MDF identification block)");
  }
  std::string v3 = "MDF     3.30    ";
  v3.resize(4096, '\0');
  write_bytes(t.path() / "v3.mf4", v3);
  EXPECT_EQ(detect_format(t.path() / "v3.mf4"), LogFormat::mdf4);
  try {
    open_log(t.path() / "v3.mf4", LogFormat::mdf4);
    ADD_FAILURE() << "MDF 3 read as MDF4";
  } catch (const LogError& e) {
    EXPECT_NE(std::string(e.what()).find("v3.mf4: MDF version 3.30, not 4.x"), std::string::npos) << e.what();
  }
  // The identification block and nothing more: no header block.
  write_bytes(t.path() / "short.mf4", written(LogFormat::mdf4, sample_frames(10)).substr(0, 64));
  EXPECT_THROW(open_log(t.path() / "short.mf4", LogFormat::mdf4), LogError);
}

// ---------------------------------------------------------------------------------------------
// Files built here block by block, for what neither the corpus nor lptn's writer has.

template <class T>
void put(std::string& out, T v) {
  for (std::size_t i = 0; i < sizeof(T); ++i) out.push_back(static_cast<char>((static_cast<std::uint64_t>(v) >> (8 * i)) & 0xFF));
}
void put_f64(std::string& out, double d) {
  std::uint64_t bits;
  std::memcpy(&bits, &d, sizeof d);
  put(out, bits);
}

class Builder {
 public:
  Builder() {
    out_ = "MDF     4.10    test    ";
    out_.resize(64, '\0');
    out_[28] = static_cast<char>(410 & 0xFF);
    out_[29] = static_cast<char>(410 >> 8);
    std::string hd;
    put<std::uint64_t>(hd, kStartNs);
    hd.resize(32, '\0');
    block("HD", {0, 0, 0, 0, 0, 0}, hd);
  }
  static constexpr std::uint64_t kStartNs = 1700000000ull * 1000000000ull;

  std::uint64_t block(const char* id, const std::vector<std::uint64_t>& links, const std::string& data) {
    const std::uint64_t at = out_.size();
    out_ += "##";
    out_ += id;
    put<std::uint32_t>(out_, 0);
    put<std::uint64_t>(out_, 24 + 8 * links.size() + data.size());
    put<std::uint64_t>(out_, links.size());
    for (std::uint64_t l : links) put(out_, l);
    out_ += data;
    out_.append((8 - out_.size() % 8) % 8, '\0');
    return at;
  }
  void link(std::uint64_t at, std::size_t i, std::uint64_t to) {
    for (std::size_t b = 0; b < 8; ++b) out_[at + 24 + 8 * i + b] = static_cast<char>((to >> (8 * b)) & 0xFF);
  }
  std::uint64_t text(const std::string& s) { return block("TX", {}, s + '\0'); }
  std::uint64_t linear(double p1, double p2) {
    std::string cc = {1, 0, 0, 0, 0, 0, 2, 0};
    cc.append(16, '\0');
    put_f64(cc, p1);
    put_f64(cc, p2);
    return block("CC", {0, 0, 0, 0}, cc);
  }
  // A channel: its name, type, data type, bit offset, byte offset, bit count; conversion, data link.
  std::uint64_t channel(const std::string& name, std::uint8_t type, std::uint8_t data_type, std::uint8_t bit,
                        std::uint32_t byte, std::uint32_t bits, std::uint64_t cc = 0, std::uint64_t data = 0,
                        std::uint8_t sync = 0) {
    std::string d = {static_cast<char>(type), static_cast<char>(sync), static_cast<char>(data_type), static_cast<char>(bit)};
    put(d, byte);
    put(d, bits);
    d.resize(72, '\0');
    return block("CN", {0, 0, text(name), 0, cc, data, 0, 0}, d);
  }
  // Channels chained in order under `first`'s next link.
  void chain(const std::vector<std::uint64_t>& cns) {
    for (std::size_t i = 1; i < cns.size(); ++i) link(cns[i - 1], 0, cns[i]);
  }
  std::uint64_t group(std::uint64_t record_id, std::uint32_t bytes, std::uint16_t flags) {
    std::string d;
    put(d, record_id);
    put<std::uint64_t>(d, 0);
    put(d, flags);
    put<std::uint16_t>(d, '.');
    put<std::uint32_t>(d, 0);
    put(d, bytes);
    put<std::uint32_t>(d, 0);
    return block("CG", {0, 0, 0, 0, 0, 0}, d);
  }
  std::uint64_t data_group(std::uint8_t id_size) {
    std::string d(8, '\0');
    d[0] = static_cast<char>(id_size);
    return block("DG", {0, 0, 0, 0}, d);
  }
  std::string& bytes() { return out_; }

 private:
  std::string out_;
};

std::string deflated(const std::string& in) {
  uLongf n = compressBound(static_cast<uLong>(in.size()));
  std::string out(n, '\0');
  compress2(reinterpret_cast<Bytef*>(out.data()), &n, reinterpret_cast<const Bytef*>(in.data()),
            static_cast<uLong>(in.size()), 9);
  out.resize(n);
  return out;
}

// Data group 1, sorted: Timestamp u32 in units of 10 us (a linear conversion); ID u32 with IDE at
// bit 31; DLC; data bytes VLSD in SD blocks (offset u64). 17-byte records in `dt_blocks` DT blocks split
// inside a record, listed by a DL with offsets (one DT block: linked directly); the signal data in a
// DL of two SD blocks.
// Data group 2, unsorted with 2-byte record ids: one CAN_DataFrame group with a float time stamp,
// 8 fixed data bytes, a BusChannel; its records in one DZ block, plain deflate.
// The two groups' frames interleave in time.
struct Built {
  std::string bytes;
  std::vector<Stamped> frames;  // in time order
  std::uint64_t dt[3] = {0, 0, 0};
};

Built build(int sorted_records, int dt_blocks, bool second_group = true) {
  Builder b;
  Built out;
  const std::uint64_t dg1 = b.data_group(0);
  b.link(64, 0, dg1);
  const std::uint64_t cg1 = b.group(0, 17, 2);
  b.link(dg1, 1, cg1);
  std::string records, sd;
  for (int k = 0; k < sorted_records; ++k) {
    const TimeUs t = static_cast<TimeUs>(Builder::kStartNs / 1000) + 20000LL * k;
    CanFrame f = make_frame(k % 2 ? 0x1234567u + static_cast<std::uint32_t>(k) : 0x300u + static_cast<std::uint32_t>(k), k % 2,
                       {});
    f.len = static_cast<std::uint8_t>(k % 9);
    for (int i = 0; i < f.len; ++i) f.data[i] = static_cast<std::uint8_t>(k * 3 + i);
    out.frames.push_back({t, f, "1"});
    put<std::uint32_t>(records, static_cast<std::uint32_t>(2000 * k));
    put<std::uint32_t>(records, f.id | (f.extended ? 0x80000000u : 0));
    records.push_back(static_cast<char>(f.len));
    put<std::uint64_t>(records, sd.size());
    put<std::uint32_t>(sd, f.len);
    sd.append(reinterpret_cast<const char*>(f.data), f.len);
  }
  // SD: two blocks under a DL (equal length: the first block's length).
  const std::size_t sd_half = sd.size() / 2;
  const std::uint64_t sd1 = b.block("SD", {}, sd.substr(0, sd_half)), sd2 = b.block("SD", {}, sd.substr(sd_half));
  std::string sd_dl = {1, 0, 0, 0};
  put<std::uint32_t>(sd_dl, 2);
  put<std::uint64_t>(sd_dl, sd_half);
  const std::uint64_t sd_list = b.block("DL", {0, sd1, sd2}, sd_dl);
  const std::uint64_t time1 = b.channel("Timestamp", 2, 0, 0, 0, 32, b.linear(0, 1e-5), 0, 1);
  const std::uint64_t can1 = b.channel("CAN_DataFrame", 0, 10, 0, 4, 13 * 8);
  const std::uint64_t id1 = b.channel("CAN_DataFrame.ID", 0, 0, 0, 4, 29);
  b.chain({id1, b.channel("CAN_DataFrame.IDE", 0, 0, 7, 7, 1), b.channel("CAN_DataFrame.DLC", 0, 0, 0, 8, 4),
           b.channel("CAN_DataFrame.DataBytes", 1, 10, 0, 9, 64, 0, sd_list)});
  b.link(can1, 1, id1);
  b.link(time1, 0, can1);
  b.link(cg1, 1, time1);
  // DT blocks cut at arbitrary bytes, listed with their offsets.
  std::vector<std::uint64_t> dl_links = {0};
  std::string dl = {0, 0, 0, 0};
  put<std::uint32_t>(dl, static_cast<std::uint32_t>(dt_blocks));
  for (int i = 0; i < dt_blocks; ++i) {
    const std::size_t from = records.size() * static_cast<std::size_t>(i) / static_cast<std::size_t>(dt_blocks) + (i ? 5 : 0);
    const std::size_t to = records.size() * static_cast<std::size_t>(i + 1) / static_cast<std::size_t>(dt_blocks) +
                           (i + 1 < dt_blocks ? 5 : 0);
    out.dt[i] = b.block("DT", {}, records.substr(from, to - from));
    dl_links.push_back(out.dt[i]);
    put<std::uint64_t>(dl, from);
  }
  // One block: linked from the data group itself.
  b.link(dg1, 2, dt_blocks == 1 ? out.dt[0] : b.block("DL", dl_links, dl));
  if (!second_group) {
    out.bytes = b.bytes();
    return out;
  }

  const std::uint64_t dg2 = b.data_group(2);
  b.link(dg1, 0, dg2);
  const std::uint64_t cg2 = b.group(0x1234, 8 + 4 + 1 + 1 + 8, 2 | 4);
  b.link(dg2, 1, cg2);
  const std::uint64_t time2 = b.channel("Timestamp", 2, 4, 0, 0, 64, 0, 0, 1);
  const std::uint64_t can2 = b.channel("CAN_DataFrame", 0, 10, 0, 8, 14 * 8);
  const std::uint64_t id2 = b.channel("CAN_DataFrame.ID", 0, 0, 0, 8, 11);
  b.chain({id2, b.channel("CAN_DataFrame.DataLength", 0, 0, 0, 12, 4),
           b.channel("CAN_DataFrame.BusChannel", 0, 0, 0, 13, 8),
           b.channel("CAN_DataFrame.DataBytes", 0, 10, 0, 14, 64)});
  b.link(can2, 1, id2);
  b.link(time2, 0, can2);
  b.link(cg2, 1, time2);
  std::string unsorted;
  for (int k = 0; k < 50; ++k) {
    const TimeUs t = static_cast<TimeUs>(Builder::kStartNs / 1000) + 10000 + 40000LL * k;
    CanFrame f = make_frame(0x7F0u + static_cast<std::uint32_t>(k % 8), false, {1, 2, 3, 4, 5, 6, 7, static_cast<std::uint8_t>(k)});
    out.frames.push_back({t, f, "3"});
    put<std::uint16_t>(unsorted, 0x1234);
    put_f64(unsorted, static_cast<double>(t - static_cast<TimeUs>(Builder::kStartNs / 1000)) / 1e6);
    put<std::uint32_t>(unsorted, f.id);
    unsorted.push_back(8);
    unsorted.push_back(3);
    unsorted.append(reinterpret_cast<const char*>(f.data), 8);
  }
  std::string dz = "DT";
  dz.push_back('\0');  // deflate
  dz.push_back('\0');
  put<std::uint32_t>(dz, 0);
  put<std::uint64_t>(dz, unsorted.size());
  const std::string z = deflated(unsorted);
  put<std::uint64_t>(dz, z.size());
  dz += z;
  b.link(dg2, 2, b.block("DZ", {}, dz));
  out.bytes = b.bytes();
  std::stable_sort(out.frames.begin(), out.frames.end(), [](const Stamped& x, const Stamped& y) { return x.t < y.t; });
  return out;
}

TEST(Mdf4Reader, SortedAndUnsortedGroupsSignalDataListsAndPlainDeflateMergedInTime) {
  TempDir t;
  const Built built = build(100, 2);
  write_bytes(t.path() / "built.mf4", built.bytes);
  const Read r = read_log(t.path() / "built.mf4");
  EXPECT_TRUE(r.bad.empty()) << r.bad.front();
  ASSERT_EQ(r.frames.size(), 150u);
  EXPECT_EQ(lines(r.frames), lines(built.frames));
}

// A DT block of a sorted group lost in the middle (its header overwritten): one bad record naming
// its offset; the blocks after it are read from the first whole record their DL offset gives.
TEST(Mdf4Reader, ALostDtBlockOfASortedGroupIsOneBadRecordAndTheNextBlockIsReadFromItsFirstWholeRecord) {
  TempDir t;
  Built built = build(300, 3);
  built.bytes[built.dt[1] + 2] = 'X';
  write_bytes(t.path() / "lost.mf4", built.bytes);
  const Read r = read_log(t.path() / "lost.mf4");
  ASSERT_EQ(r.bad.size(), 1u);
  EXPECT_EQ(r.bad[0], (t.path() / "lost.mf4").string() + ": byte " + std::to_string(built.dt[1]) +
                          ": data block: a block of another type than expected there; its records are not read");
  // Block 1 holds bytes [0, 1705) (records 0..99 whole, 100 in part), block 2 [1705, 3405),
  // block 3 [3405, 5100): records 0..99, then from record 201 (at byte 3417) on.
  std::vector<Stamped> expected;
  for (const Stamped& s : built.frames) {
    if (s.channel == "3") {
      expected.push_back(s);
      continue;
    }
    const long long k = (s.t - static_cast<TimeUs>(Builder::kStartNs / 1000)) / 20000;
    if (k < 100 || k >= 201) expected.push_back(s);
  }
  EXPECT_EQ(lines(r.frames), lines(expected));
}

// A finalized file whose one DT block the file ends inside: the records before the cut, then one
// bad record naming the block.
TEST(Mdf4Reader, ADtBlockCutShortIsReadUpToTheCutAndReportedOnce) {
  TempDir t;
  const Built built = build(100, 1, false);
  const fs::path p = t.path() / "cut.mf4";
  for (const std::size_t records : {40u, 41u}) {  // inside a record; at a record's end
    write_bytes(p, built.bytes.substr(0, built.dt[0] + 24 + 17 * records + (records == 40 ? 5 : 0)));
    const Read r = read_log(p);
    ASSERT_EQ(r.bad.size(), 1u) << r.bad[1];
    EXPECT_EQ(r.bad[0], p.string() + ": byte " + std::to_string(built.dt[0]) + ": data block: the file ends inside " +
                            (records == 40 ? "a record" : "the block") + " (cut short)");
    EXPECT_EQ(lines(r.frames), lines({built.frames.begin(), built.frames.begin() + records}));
  }
}

// What the fuzzer found (tests/fuzz/corpus/fuzz_mdf4/sorted_records_of_no_bytes.mf4): a sorted data
// group whose records are 0 bytes long was read forever. Now it is a damaged data group.
TEST(Mdf4Reader, ASortedGroupOfZeroByteRecordsIsOneBadRecordNotAnEndlessRead) {
  TempDir t;
  Builder b;
  const std::uint64_t dg = b.data_group(0);
  b.link(64, 0, dg);
  b.link(dg, 1, b.group(0, 0, 2));
  b.link(dg, 2, b.block("DT", {}, std::string(64, '\1')));
  write_bytes(t.path() / "zero.mf4", b.bytes());
  const Read r = read_log(t.path() / "zero.mf4");
  ASSERT_EQ(r.bad.size(), 1u);
  EXPECT_EQ(r.bad[0], (t.path() / "zero.mf4").string() + ": byte " + std::to_string(dg) +
                          ": data group (##DG): sorted, and its records are of no bytes; its frames are not read");
  EXPECT_TRUE(r.frames.empty());
}

}  // namespace
}  // namespace lptn::canfile
