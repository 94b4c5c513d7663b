// Where a replay gets its frames, one record of a log at a time: the interface every CAN log reader
// implements, and candump -L's reader here (what the daemon replays on the target, where the rest of
// the CAN wing's host side is not built); Vector ASC, BLF and MDF4 on the host (can/canfile).
#pragma once

#include <cstddef>
#include <cstdio>
#include <string_view>

#include "lptn/firmware/candump_line.hpp"
#include "hostio/line_reader.hpp"
#include "lptn/firmware/can_frame.hpp"
#include "lptn/firmware/input.hpp"

namespace lptn::frames {

class FrameSource {
 public:
  enum class Status { frame, bad, end };
  virtual ~FrameSource() = default;
  // `frame`: the next frame and its time stamp; `bad`: a record that is no frame, `why` (a static
  // string) says what is wrong with it; `end`: nothing more. Records that carry no frame and are
  // no error (a log's header, comments, a BLF's other objects) are passed over.
  virtual Status next(fw::TimeUs& time_us, fw::CanFrame& frame, const char*& why) = 0;
  // 1-based number of the record last returned: a line, or a BLF object.
  virtual std::size_t record() const = 0;
  // What a record is called in a message: "line" or "object".
  virtual const char* record_name() const = 0;
  // The bus the frame last returned came from: candump's interface name ("can0"), ASC's and BLF's
  // channel number ("1"). Valid until the next call of next().
  virtual std::string_view channel() const = 0;
};

// candump -L, one frame per line (lptn/firmware/candump_line.hpp), through a line reader: one
// with next(std::string_view&) giving LineReader::Status and line_number(). The daemon's is
// hostio's LineReader on the FILE* (allocates nothing); the host's log readers give a reader of
// 256 KiB blocks (can/canfile), the same lines read faster.
template <class Reader>
class CandumpLines : public FrameSource {
 public:
  explicit CandumpLines(std::FILE* log) : reader_(log) {}
  Status next(fw::TimeUs& time_us, fw::CanFrame& frame, const char*& why) override {
    std::string_view line;
    for (hostio::LineReader::Status s; (s = reader_.next(line)) != hostio::LineReader::Status::end;) {
      if (s == hostio::LineReader::Status::too_long) {
        why = "line longer than 512 bytes, not a candump line";
        return Status::bad;
      }
      if (line.empty()) continue;
      // The record is the reader's own, not cleared for every line: the parse sets all of it.
      if ((why = fw::parse_candump_line(line, record_)) != nullptr) return Status::bad;
      time_us = record_.time_us;
      frame = record_.frame;
      channel_ = record_.interface;
      return Status::frame;
    }
    return Status::end;
  }
  std::size_t record() const override { return reader_.line_number(); }
  const char* record_name() const override { return "line"; }
  std::string_view channel() const override { return channel_; }

 private:
  Reader reader_;
  fw::CandumpRecord record_;
  std::string_view channel_;
};

// The daemon's: a line at a time from the FILE*. Allocates nothing.
using CandumpSource = CandumpLines<hostio::LineReader>;

}  // namespace lptn::frames
