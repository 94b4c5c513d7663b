// The readers and writers behind can_log.hpp, one file per format.
#pragma once

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include "tools/canfile/can_log.hpp"

namespace lptn::canfile {

// An open file, closed with its owner.
using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

std::unique_ptr<fw::FrameSource> make_candump_source(File file);
std::unique_ptr<fw::FrameSource> make_asc_source(File file);
// Reads the file header; throws LogError naming `path` if it is not a BLF's.
std::unique_ptr<fw::FrameSource> make_blf_source(File file, const std::filesystem::path& path);

std::unique_ptr<LogWriter> make_candump_writer(const std::string& interface);
std::unique_ptr<LogWriter> make_asc_writer();
std::unique_ptr<LogWriter> make_blf_writer();

// For detecting the format: a line of an ASC file's header (date, base, Begin Triggerblock, ...).
bool is_asc_header_line(std::string_view line);

// BLF files begin with these four bytes.
inline constexpr char kBlfMagic[] = "LOGG";

}  // namespace lptn::canfile
