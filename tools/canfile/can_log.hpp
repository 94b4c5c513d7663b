// CAN log files as engineers bring them: candump -L (can-utils), Vector ASC and Vector BLF, read
// frame by frame and written whole. Readers are replay's frame sources (firmware/linux), so
// `lptn replay` and `lptn convert` take any of the three through the same code.
#pragma once

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "firmware/linux/frame_source.hpp"
#include "lptn/firmware/can_frame.hpp"
#include "lptn/firmware/input.hpp"

namespace lptn::canfile {

enum class LogFormat { candump, asc, blf };

// "candump", "asc", "blf".
const char* format_name(LogFormat f);
std::optional<LogFormat> format_from_name(std::string_view name);
// The format a file of this name is written in: *.log candump, *.asc, *.blf; else none.
std::optional<LogFormat> format_from_extension(const std::filesystem::path& file);

// A log that cannot be opened or is in no format lptn reads: one line naming the file.
class LogError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What the file holds, by its content first (BLF's "LOGG"; a candump line; ASC's header or event
// lines among the first non-empty lines), else by its extension (a damaged log may start with
// garbage). Throws LogError where neither says.
LogFormat detect_format(const std::filesystem::path& file);

// A reader of `file` in `format`. Throws LogError if it cannot be opened, or a BLF's file header
// is not one.
std::unique_ptr<fw::FrameSource> open_log(const std::filesystem::path& file, LogFormat format);
// The same for an open stream (which the reader closes; BLF's must be seekable), `name` for messages.
std::unique_ptr<fw::FrameSource> open_log(std::FILE* stream, LogFormat format, const std::string& name);

// Writes a log whole: frames in time order, then the file's bytes (text or binary).
class LogWriter {
 public:
  virtual ~LogWriter() = default;
  virtual void add(fw::TimeUs time_us, const fw::CanFrame& frame) = 0;
  virtual std::string finish() = 0;
};

// candump: `interface` names the bus on every line (at most 15 characters). ASC and BLF: channel 1,
// the frames received (Rx); ASC's and BLF's time stamps count from the first frame, whose time is
// the file's start (ASC's date line to the millisecond, BLF's header to the millisecond and the
// objects' offsets to the nanosecond).
std::unique_ptr<LogWriter> make_log_writer(LogFormat format, const std::string& interface = "can0");

}  // namespace lptn::canfile
