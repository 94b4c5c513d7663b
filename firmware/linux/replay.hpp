// Replay of a CAN log through the estimator, as fast as the CPU allows: the frames' time
// stamps drive the ticks (lptn/firmware/replay_clock.hpp says how). Shared by `lptn replay` (calibration from JSON)
// and `lptn-daemon --replay` (calibration compiled in), so the two differ in nothing else.
#pragma once

#include <cstddef>
#include <cstdio>
#include <functional>
#include <string>

#include "lptn/firmware/candump_line.hpp"
#include "can/frames/frame_source.hpp"
#include "lptn/firmware/estimator.hpp"
#include "lptn/firmware/replay_clock.hpp"

namespace lptn::fw {

// The clock's counts (frames, ticks, rows, ...) and the log's records.
struct ReplayStats : ReplayCounts {
  std::size_t records = 0;     // lines of a text log, objects of a BLF, as far as read
  std::size_t bad_records = 0; // malformed, reported and skipped
};

struct ReplaySinks {
  // Every tick once the estimator is initialized, with the log's first time stamp.
  std::function<void(const EstimatorOutput<double>&, TimeUs log_start_us)> row;
  // A malformed record (1-based number) and why; replay goes on with the next one.
  std::function<void(std::size_t record, const char* reason)> bad_record;
  // Called every `progress_every` frames (for a progress line); may be empty.
  std::function<void(const ReplayStats&)> progress;
  std::size_t progress_every = 1000000;
};

ReplayStats replay_frames(frames::FrameSource& log, Estimator<double>& estimator, const ReplaySinks& sinks);

inline ReplayStats replay_candump(std::FILE* log, Estimator<double>& estimator, const ReplaySinks& sinks) {
  frames::CandumpSource source(log);
  return replay_frames(source, estimator, sinks);
}

}  // namespace lptn::fw
