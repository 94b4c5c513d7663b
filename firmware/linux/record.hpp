// A daemon's record (`lptn-daemon --record`) replayed through an estimator. The record holds what
// the daemon's estimator was given, in order: each received frame (interface rx) stamped with the
// time the estimator was told, each receive-buffer overrun the kernel reported (interface overrun),
// each tick's frames (interface tx) stamped with the tick's time. An
// estimator with the daemon's configuration, fed the rx frames and ticked at the tx stamps, makes
// the tx frames bit for bit however late the daemon's timer fired or its frames came: what does
// not is a fault of the daemon or of the record.
#pragma once

#include <cstddef>
#include <filesystem>

#include "lptn/firmware/estimator.hpp"
#include "lptn/firmware/output_frames.hpp"

namespace lptn::fw {

struct RecordReplay {
  std::size_t received = 0;        // rx frames given to the estimator
  std::size_t overruns = 0;        // receive-buffer overruns (interface overrun) told to the estimator
  std::size_t ticks = 0;           // ticks replayed (a run of tx lines with one stamp each)
  std::size_t ticks_differing = 0; // of them, ticks whose recorded frames are not the estimator's
  std::size_t first_differing = 0; // the first of those (1-based; 0: none)
  std::size_t bad_lines = 0;       // lines that are not candump frames, or on another interface
};

// Throws std::runtime_error if the file cannot be read. `ids`: the CAN ids the daemon sends on.
RecordReplay replay_record(const std::filesystem::path& record, Estimator<double>& estimator,
                           const OutputId (&ids)[kMaxOutputFrames]);

// Same id, kind, length and data bytes.
bool same_frame(const CanFrame& a, const CanFrame& b);

}  // namespace lptn::fw
