#include "replay.hpp"

namespace lptn::fw {

ReplayStats replay_frames(frames::FrameSource& log, Estimator<double>& estimator, const ReplaySinks& sinks) {
  ReplayStats stats;
  ReplayClock<double> clock(estimator);
  auto row = [&](const EstimatorOutput<double>& out, TimeUs first_us) {
    if (sinks.row) sinks.row(out, first_us);
  };
  auto copy_counts = [&] { static_cast<ReplayCounts&>(stats) = clock.counts(); };
  TimeUs time_us = 0;
  CanFrame frame;
  const char* why = nullptr;
  // The frame count of the next progress call: a count, where a remainder of the count by
  // progress_every was a 64-bit division every frame (2 % of a replay).
  std::size_t next_progress = sinks.progress_every;
  for (frames::FrameSource::Status status; (status = log.next(time_us, frame, why)) != frames::FrameSource::Status::end;) {
    stats.records = log.record();
    if (status == frames::FrameSource::Status::bad) {
      ++stats.bad_records;
      if (sinks.bad_record) sinks.bad_record(stats.records, why);
      continue;
    }
    clock.frame(time_us, frame, row);
    if (clock.counts().frames == next_progress && sinks.progress) {
      next_progress += sinks.progress_every;
      copy_counts();
      sinks.progress(stats);
    }
  }
  clock.finish(row);
  copy_counts();
  return stats;
}

}  // namespace lptn::fw
