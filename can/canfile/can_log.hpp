// CAN log files as engineers bring them: candump -L (can-utils), Vector ASC, Vector BLF and ASAM MDF4
// bus logging files, read frame by frame and written whole. Readers are replay's frame sources
// (can/frames), so `lptn replay` and `lptn convert` take any of them through the same code.
#pragma once

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "can/frames/frame_source.hpp"
#include "hostio/bad_input.hpp"
#include "lptn/firmware/can_frame.hpp"
#include "lptn/firmware/input.hpp"

namespace lptn::canfile {

enum class LogFormat { candump, asc, blf, mdf4 };

// "candump", "asc", "blf", "mdf4".
const char* format_name(LogFormat f);
std::optional<LogFormat> format_from_name(std::string_view name);
// The format a file of this name is written in: *.log candump, *.asc, *.blf, *.mf4; else none.
std::optional<LogFormat> format_from_extension(const std::filesystem::path& file);
// ".log", ".asc", ".blf", ".mf4".
const char* format_extension(LogFormat f);

// Readers report a log's malformed records one by one up to this many, then as a count.
inline constexpr std::size_t kRecordMessagesShown = 10;

// "FILE:LINE: reason" for a text log's line, "FILE: object N: reason" for a BLF's object, "FILE: reason"
// for an MDF4 file (whose reasons name the block's byte offset).
std::string record_message(const std::filesystem::path& file, const frames::FrameSource& source, std::size_t record,
                           std::string_view reason);

// A log that cannot be opened or is in no format lptn reads: one line naming the file.
class LogError : public hostio::BadInput {
 public:
  using BadInput::BadInput;
};

// What the file holds, by its content first (BLF's "LOGG"; MDF4's identification block; a candump line; ASC's header or event
// lines among the first non-empty lines), else by its extension (a damaged log may start with
// garbage). Throws LogError where neither says.
LogFormat detect_format(const std::filesystem::path& file);

// A reader of `file` in `format`. Throws LogError if it cannot be opened, or a BLF's file header
// or an MDF4's identification and header blocks are not one.
std::unique_ptr<frames::FrameSource> open_log(const std::filesystem::path& file, LogFormat format);
// The same for an open stream (which the reader closes; BLF's and MDF4's must be seekable), `name` for messages.
std::unique_ptr<frames::FrameSource> open_log(std::FILE* stream, LogFormat format, const std::string& name);

// The frames of one channel of a log ("" for all of them), and which channels the log holds: a
// recorder's log may hold several buses, and two that both carry the converter's ids must not be
// read as one.
class ChannelFilter final : public frames::FrameSource {
 public:
  ChannelFilter(std::unique_ptr<frames::FrameSource> source, std::string wanted)
      : source_(std::move(source)), wanted_(std::move(wanted)) {}
  Status next(fw::TimeUs& time_us, fw::CanFrame& frame, const char*& why) override;
  std::size_t record() const override { return source_->record(); }
  const char* record_name() const override { return source_->record_name(); }
  std::string_view channel() const override { return source_->channel(); }

  // The channels that carried frames, in the order they first did.
  const std::vector<std::string>& channels() const { return channels_; }
  // "1, 2": for messages.
  std::string channel_list() const;

 private:
  std::unique_ptr<frames::FrameSource> source_;
  std::string wanted_;
  std::vector<std::string> channels_;
};

// Which log to read and how: the format (none: detect_format) and the channel ("": all).
struct LogSelection {
  std::optional<LogFormat> format;
  std::string channel;
};

struct OpenedLog {
  LogFormat format;
  std::unique_ptr<ChannelFilter> frames;
};

// open_log with the selection's format, or the detected one, and its channel filter.
OpenedLog open_log(const std::filesystem::path& file, const LogSelection& selection);

// After reading: "" if the channels were as they should be; else one line naming the file, and
// `fatal` says whether it is an error (the channel asked for carried no frame) or a warning
// (frames of several channels read as one bus).
std::string channel_problem(const std::filesystem::path& file, const ChannelFilter& frames,
                            const LogSelection& selection, bool& fatal);

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
// objects' offsets to the nanosecond). MDF4: CAN_DataFrame, CAN_RemoteFrame and CAN_ErrorFrame on
// bus channel 1 (can/canfile/mdf4_write.cpp), the header's start time the first frame's.
std::unique_ptr<LogWriter> make_log_writer(LogFormat format, const std::string& interface = "can0");

}  // namespace lptn::canfile
