// The readers and writers behind can_log.hpp, one file per format.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include "can/canfile/can_log.hpp"

namespace lptn::canfile {

// An open file, closed with its owner.
using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

std::unique_ptr<frames::FrameSource> make_candump_source(File file);
std::unique_ptr<frames::FrameSource> make_asc_source(File file);
// Reads the file header; throws LogError naming `path` if it is not a BLF's.
std::unique_ptr<frames::FrameSource> make_blf_source(File file, const std::filesystem::path& path);
// Reads the identification and header blocks and the data groups' channel groups; throws LogError
// naming `path` if the first two are not an MDF4 file's (mdf4_read.cpp).
std::unique_ptr<frames::FrameSource> make_mdf4_source(File file, const std::filesystem::path& path);

std::unique_ptr<LogWriter> make_candump_writer(const std::string& interface);
std::unique_ptr<LogWriter> make_asc_writer();
std::unique_ptr<LogWriter> make_blf_writer();
std::unique_ptr<LogWriter> make_mdf4_writer();

// For detecting the format: a line of an ASC file's header (date, base, Begin Triggerblock, ...).
bool is_asc_header_line(std::string_view line);

// CAN FD's data length codes 0..15 and the lengths they stand for.
inline constexpr std::uint8_t kFdLengths[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64};

// The smallest code whose length holds `length` bytes.
inline std::uint8_t fd_length_code(std::uint8_t length) {
  std::uint8_t code = 0;
  while (code < 15 && kFdLengths[code] < length) ++code;
  return code;
}

// BLF files begin with these four bytes.
inline constexpr char kBlfMagic[] = "LOGG";
// MDF4 files begin with one of these (the second while a logger writes them).
inline constexpr char kMdfMagic[] = "MDF     ";
inline constexpr char kMdfUnfinishedMagic[] = "UnFinMF ";

}  // namespace lptn::canfile
