// ASAM MDF 4.1 as mdf4_read.cpp and mdf4_write.cpp use it: the block layouts, little-endian all.
//
// Every block starts with a 24-byte header: "##" and two letters, 4 reserved bytes, the block's
// length (u64, header included, padding to 8 bytes not) and its link count (u64); then that many
// links (u64 file offsets, 0 for none); then the block's data. The file starts with the 64-byte
// identification block (not a "##" block): "MDF     " ("UnFinMF " while a logger still writes
// it; kMdfMagic, kMdfUnfinishedMagic in formats.hpp), the version "4.10    ", the program, and at
// byte 60 the unfinalized flags.
//
//   ##HD at 64: links dg_first, fh_first, ch_first, at_first, ev_first, md_comment;
//                data start time (u64 ns since 1970 UTC), tz and dst offsets (i16 minutes), flags.
//   ##DG: links dg_next, cg_first, data, md_comment; data record id size (u8: 0, 1, 2, 4, 8).
//   ##CG: links cg_next, cn_first, tx_acq_name, si_acq_source, sr_first, md_comment;
//                data record id (u64), cycle count (u64), flags (u16: 1 VLSD group, 2 bus event,
//                4 plain bus event), path separator (u16), 4 reserved, data bytes (u32), invalidation
//                bytes (u32). A VLSD group's records are a u32 length and that many bytes.
//   ##CN: links cn_next, composition, tx_name, si_source, cc_conversion, data (VLSD: the SD block
//                or the VLSD channel group), md_unit, md_comment, ...; data channel type (u8: 0 fixed,
//                1 VLSD, 2 master, 3 virtual master, 6 virtual data), sync type (u8: 1 time), data type
//                (u8: 0/1 unsigned LE/BE, 2/3 signed, 4/5 float, 10 byte array), bit offset (u8),
//                byte offset (u32), bit count (u32), flags (u32), ...
//   ##CC: links tx_name, md_unit, md_comment, cc_inverse, refs...; data type (u8: 0 identity,
//                1 linear p1 + p2 x, 2 rational, 4/5 value to value with/without interpolation),
//                precision (u8), flags (u16), ref count (u16), value count (u16), range (2 f64),
//                values (f64).
//   ##TX / ##MD: text, zero-terminated.  ##SI: links tx_name, tx_path, md_comment; data source type,
//                bus type (2 CAN).
//   ##DT / ##SD: records / signal data.  ##DL: links dl_next, data blocks...; data flags (u8: 1
//                equal length), 3 reserved, count (u32), then equal length (u64) or offsets (u64 each).
//   ##HL: links dl_first; data flags (u16), zip type (u8).
//   ##DZ: no links; data original block type ("DT", "SD"), zip type (u8: 0 deflate, 1 transposition
//                then deflate), reserved, zip parameter (u32: transposition's column count), original
//                length (u64), zipped length (u64), zipped bytes.
//
// The bus logging convention (ASAM MDF "Bus Logging" associated standard): a CAN bus's frames are
// channel groups with the bus event flag whose composed channel CAN_DataFrame (CAN_RemoteFrame,
// CAN_ErrorFrame) holds the members .BusChannel, .ID (29 bits), .IDE, .DLC, .DataLength,
// .DataBytes (fixed length or VLSD), .Dir, .EDL, .BRS, ...; the master channel is the time stamp in
// seconds (after its conversion) since the header's start time.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>

namespace lptn::canfile::mdf4 {

inline constexpr std::size_t kIdBlockSize = 64;
inline constexpr std::size_t kHeaderSize = 24;
// Unfinalized flags: the last DT block's length was not updated (it runs to the file's end).
inline constexpr std::uint16_t kUnfinDtLength = 0x4;

enum CgFlags : std::uint16_t { kCgVlsd = 1, kCgBusEvent = 2, kCgPlainBusEvent = 4 };
enum ChannelType : std::uint8_t { kCnFixed = 0, kCnVlsd = 1, kCnMaster = 2, kCnVirtualMaster = 3, kCnSync = 4,
                                  kCnMaxLength = 5, kCnVirtualData = 6 };
enum DataType : std::uint8_t { kUintLe = 0, kUintBe = 1, kIntLe = 2, kIntBe = 3, kFloatLe = 4, kFloatBe = 5,
                               kByteArray = 10 };
enum ZipType : std::uint8_t { kDeflate = 0, kTransposeDeflate = 1 };

template <class T>
T get(const std::uint8_t* p) {
  T v = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) v = static_cast<T>(v | static_cast<T>(static_cast<T>(p[i]) << (8 * i)));
  return v;
}

inline double get_f64(const std::uint8_t* p) {
  const std::uint64_t bits = get<std::uint64_t>(p);
  double d;
  std::memcpy(&d, &bits, sizeof d);
  return d;
}

template <class T>
void put(std::string& out, T v) {
  for (std::size_t i = 0; i < sizeof(T); ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

inline void put_f64(std::string& out, double d) {
  std::uint64_t bits;
  std::memcpy(&bits, &d, sizeof d);
  put(out, bits);
}

// Transposition as DZ type 1 stores it: `columns` bytes per row, the rows' first bytes first, ...;
// the bytes after the last whole row as they are.
inline void transpose(const std::uint8_t* in, std::uint8_t* out, std::size_t size, std::size_t columns, bool forward) {
  const std::size_t rows = columns ? size / columns : 0;
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < columns; ++c) {
      if (forward) out[c * rows + r] = in[r * columns + c];
      else out[r * columns + c] = in[c * rows + r];
    }
  std::memcpy(out + rows * columns, in + rows * columns, size - rows * columns);
}

}  // namespace lptn::canfile::mdf4
