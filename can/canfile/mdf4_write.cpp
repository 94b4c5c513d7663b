// Writes an MDF 4.10 bus logging file (internal/mdf4_blocks.hpp), finalized: one unsorted data
// group (1-byte record ids) of three channel groups, CAN_DataFrame (1), CAN_RemoteFrame (2) and
// CAN_ErrorFrame (3), each of the same 80-byte record:
//
//   0  Timestamp   f64, seconds since the header's start time (the first frame's time, to the ns)
//   8  ID          29 bits; IDE bit 31 (byte 11, bit 7)
//   12 DLC         4 bits
//   13 DataLength  7 bits (bytes)
//   14 BusChannel  8 bits (always 1)
//   15 Dir bit 0 (0: Rx), EDL bit 1 (CAN FD), BRS bit 2
//   16 DataBytes   64 bytes, fixed length (CAN_DataFrame only)
//
// The records go into DZ blocks (transposition by the record's 81 bytes, then deflate) of at most
// 4096 records each, listed by a DL list under an HL header, the two written before the blocks.
#include <zlib.h>

#include <cstdint>
#include <string>
#include <vector>

#include "can/canfile/internal/formats.hpp"
#include "can/canfile/internal/mdf4_blocks.hpp"

namespace lptn::canfile {
namespace {

using namespace mdf4;
using fw::CanFrame;
using fw::TimeUs;

constexpr std::uint32_t kDataBytes = 80;
constexpr std::size_t kRecord = 1 + kDataBytes;
constexpr std::size_t kRecordsPerBlock = 4096;  // 324 KiB unzipped: a damaged block loses no more

// A file being laid out: blocks appended at 8-byte boundaries, links patched once known.
class Layout {
 public:
  Layout() : out_(kIdBlockSize, '\0') {}
  // Appends a block; returns its offset.
  std::uint64_t block(const char* id, const std::vector<std::uint64_t>& links, const std::string& data) {
    const std::uint64_t at = out_.size();
    out_ += "##";
    out_ += id;
    put<std::uint32_t>(out_, 0);
    put<std::uint64_t>(out_, kHeaderSize + 8 * links.size() + data.size());
    put<std::uint64_t>(out_, links.size());
    for (std::uint64_t l : links) put(out_, l);
    out_ += data;
    out_.append((8 - out_.size() % 8) % 8, '\0');
    return at;
  }
  // Sets link `i` of the block at `at`.
  void link(std::uint64_t at, std::size_t i, std::uint64_t to) {
    for (std::size_t b = 0; b < 8; ++b) out_[at + kHeaderSize + 8 * i + b] = static_cast<char>((to >> (8 * b)) & 0xFF);
  }
  std::uint64_t text(const std::string& s) {
    std::string data = s;
    data.push_back('\0');
    return block("TX", {}, data);
  }
  std::string& bytes() { return out_; }

 private:
  std::string out_;
};

struct Member {
  const char* leaf;
  std::uint8_t data_type, bit_offset;
  std::uint32_t byte_offset, bit_count;
};

// The channel's data: type, sync, data type, bit offset, byte offset, bit count, flags, then
// invalidation bit, precision, attachments and the six f64 ranges and limits.
std::string channel_data(std::uint8_t type, std::uint8_t sync, std::uint8_t data_type, std::uint8_t bit_offset,
                         std::uint32_t byte_offset, std::uint32_t bit_count, std::uint32_t flags) {
  std::string d;
  d.push_back(static_cast<char>(type));
  d.push_back(static_cast<char>(sync));
  d.push_back(static_cast<char>(data_type));
  d.push_back(static_cast<char>(bit_offset));
  put(d, byte_offset);
  put(d, bit_count);
  put(d, flags);
  put<std::uint32_t>(d, 0);  // invalidation bit
  d.push_back('\0');         // precision
  d.push_back('\0');
  put<std::uint16_t>(d, 0);  // attachments
  d.append(6 * 8, '\0');
  return d;
}

constexpr std::uint32_t kBusEventChannel = 1u << 10;

class Mdf4Writer final : public LogWriter {
 public:
  void add(TimeUs t, const CanFrame& f) override {
    if (count_[0] + count_[1] + count_[2] == 0) start_us_ = t;
    const std::uint8_t kind = f.error ? 3 : f.remote ? 2 : 1;
    ++count_[kind - 1];
    std::string& r = records_;
    r.push_back(static_cast<char>(kind));
    put_f64(r, static_cast<double>(t - start_us_) / 1e6);
    put<std::uint32_t>(r, (f.id & 0x1FFFFFFFu) | (f.extended ? 0x80000000u : 0));
    const std::uint8_t length = f.fd ? f.len : std::min<std::uint8_t>(f.len, 8);
    r.push_back(static_cast<char>(f.fd ? fd_length_code(length) : length));
    r.push_back(static_cast<char>(length));
    r.push_back('\x01');                          // bus channel
    r.push_back(static_cast<char>(f.fd ? 2 : 0));  // Rx; EDL
    std::string data(64, '\0');
    if (!f.remote && !f.error) std::memcpy(data.data(), f.data, length);
    r += data;
  }

  std::string finish() override {
    Layout file;
    std::string id = std::string(kMdfMagic) + "4.10    " + "lptn    ";
    id.resize(kIdBlockSize, '\0');
    id[28] = static_cast<char>(410 & 0xFF);
    id[29] = static_cast<char>(410 >> 8);
    file.bytes().replace(0, kIdBlockSize, id);

    std::string hd;
    put<std::uint64_t>(hd, static_cast<std::uint64_t>(start_us_) * 1000);
    put<std::int16_t>(hd, 0);  // time zone
    put<std::int16_t>(hd, 0);  // daylight saving
    hd.append(4, '\0');        // time flags (UTC), class, flags, reserved
    hd.append(16, '\0');       // start angle and distance
    const std::uint64_t hd_at = file.block("HD", {0, 0, 0, 0, 0, 0}, hd);

    std::string fh;
    put<std::uint64_t>(fh, static_cast<std::uint64_t>(start_us_) * 1000);
    fh.append(8, '\0');
    const std::uint64_t fh_comment = file.block(
        "MD", {}, std::string("<FHcomment><TX>written by lptn convert</TX><tool_id>lptn</tool_id>"
                              "<tool_vendor>lptn</tool_vendor><tool_version>1</tool_version></FHcomment>") +
                      '\0');
    const std::uint64_t fh_at = file.block("FH", {0, fh_comment}, fh);
    file.link(hd_at, 1, fh_at);

    std::string dg(8, '\0');
    dg[0] = 1;  // record id size
    const std::uint64_t dg_at = file.block("DG", {0, 0, 0, 0}, dg);
    file.link(hd_at, 0, dg_at);

    std::uint64_t previous_cg = 0;
    static const char* const kNames[] = {"CAN_DataFrame", "CAN_RemoteFrame", "CAN_ErrorFrame"};
    for (int kind = 1; kind <= 3; ++kind) {
      const std::uint64_t cg_at = channel_group(file, kNames[kind - 1], static_cast<std::uint64_t>(kind),
                                                count_[kind - 1]);
      file.link(previous_cg ? previous_cg : dg_at, previous_cg ? 0 : 1, cg_at);
      previous_cg = cg_at;
    }
    if (!records_.empty()) file.link(dg_at, 2, data(file));
    return std::move(file.bytes());
  }

 private:
  std::uint64_t channel_group(Layout& file, const std::string& name, std::uint64_t record_id, std::uint64_t cycles) {
    std::string cg;
    put(cg, record_id);
    put(cg, cycles);
    put<std::uint16_t>(cg, kCgBusEvent | kCgPlainBusEvent);
    put<std::uint16_t>(cg, '.');
    put<std::uint32_t>(cg, 0);
    put<std::uint32_t>(cg, kDataBytes);
    put<std::uint32_t>(cg, 0);
    std::string si = {2, 2, 0, 0, 0, 0, 0, 0};  // source type bus, bus type CAN
    const std::uint64_t si_at = file.block("SI", {file.text("CAN1"), 0, 0}, si);
    const std::uint64_t cg_at = file.block("CG", {0, 0, file.text("CAN1"), si_at, 0, 0}, cg);

    const std::uint64_t time_at =
        file.block("CN", {0, 0, file.text("Timestamp"), 0, 0, 0, 0, 0}, channel_data(kCnMaster, 1, kFloatLe, 0, 0, 64, 0));
    const std::uint64_t frame_at = file.block(
        "CN", {0, 0, file.text(name), 0, 0, 0, 0, 0},
        channel_data(kCnFixed, 0, kByteArray, 0, 8, 8 * (kDataBytes - 8), kBusEventChannel));
    file.link(cg_at, 1, time_at);
    file.link(time_at, 0, frame_at);

    std::vector<Member> members = {{"BusChannel", kUintLe, 0, 14, 8}, {"ID", kUintLe, 0, 8, 29},
                                   {"IDE", kUintLe, 7, 11, 1},        {"DLC", kUintLe, 0, 12, 4},
                                   {"DataLength", kUintLe, 0, 13, 7}, {"Dir", kUintLe, 0, 15, 1},
                                   {"EDL", kUintLe, 1, 15, 1},        {"BRS", kUintLe, 2, 15, 1}};
    if (record_id == 1) members.push_back({"DataBytes", kByteArray, 0, 16, 8 * 64});
    std::uint64_t previous = 0;
    for (const Member& m : members) {
      const std::uint64_t at =
          file.block("CN", {0, 0, file.text(name + "." + m.leaf), 0, 0, 0, 0, 0},
                     channel_data(kCnFixed, 0, m.data_type, m.bit_offset, m.byte_offset, m.bit_count, kBusEventChannel));
      file.link(previous ? previous : frame_at, previous ? 0 : 1, at);
      previous = at;
    }
    return cg_at;
  }

  // The records as DZ blocks under a DL list and an HL header, the two before the blocks (so that
  // a file cut short keeps the blocks before the cut); returns the HL's offset.
  std::uint64_t data(Layout& file) {
    std::vector<std::string> zipped;
    const std::size_t chunk = kRecord * kRecordsPerBlock;
    for (std::size_t at = 0; at < records_.size(); at += chunk) {
      const std::size_t n = std::min(chunk, records_.size() - at);
      std::string transposed(n, '\0');
      transpose(reinterpret_cast<const std::uint8_t*>(records_.data() + at),
                reinterpret_cast<std::uint8_t*>(transposed.data()), n, kRecord, true);
      uLongf packed_size = compressBound(static_cast<uLong>(n));
      std::string packed(packed_size, '\0');
      compress2(reinterpret_cast<Bytef*>(packed.data()), &packed_size,
                reinterpret_cast<const Bytef*>(transposed.data()), static_cast<uLong>(n), 6);
      packed.resize(packed_size);
      std::string dz = "DT";
      dz.push_back(static_cast<char>(kTransposeDeflate));
      dz.push_back('\0');
      put<std::uint32_t>(dz, kRecord);
      put<std::uint64_t>(dz, n);
      put<std::uint64_t>(dz, packed.size());
      dz += packed;
      zipped.push_back(std::move(dz));
    }
    std::string hl;
    put<std::uint16_t>(hl, 1);  // equal length
    hl.push_back(static_cast<char>(kTransposeDeflate));
    hl.append(5, '\0');
    const std::uint64_t hl_at = file.block("HL", {0}, hl);
    std::string dl;
    dl.push_back('\x01');  // equal length
    dl.append(3, '\0');
    put<std::uint32_t>(dl, static_cast<std::uint32_t>(zipped.size()));
    put<std::uint64_t>(dl, chunk);
    const std::uint64_t dl_at = file.block("DL", std::vector<std::uint64_t>(1 + zipped.size(), 0), dl);
    file.link(hl_at, 0, dl_at);
    for (std::size_t i = 0; i < zipped.size(); ++i) file.link(dl_at, 1 + i, file.block("DZ", {}, zipped[i]));
    return hl_at;
  }

  TimeUs start_us_ = 0;
  std::uint64_t count_[3] = {0, 0, 0};
  std::string records_;
};

}  // namespace

std::unique_ptr<LogWriter> make_mdf4_writer() { return std::make_unique<Mdf4Writer>(); }

}  // namespace lptn::canfile
