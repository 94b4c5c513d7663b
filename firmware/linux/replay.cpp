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
  for (frames::FrameSource::Status status; (status = log.next(time_us, frame, why)) != frames::FrameSource::Status::end;) {
    stats.records = log.record();
    if (status == frames::FrameSource::Status::bad) {
      ++stats.bad_records;
      if (sinks.bad_record) sinks.bad_record(stats.records, why);
      continue;
    }
    clock.frame(time_us, frame, row);
    if (sinks.progress && clock.counts().frames % sinks.progress_every == 0) {
      copy_counts();
      sinks.progress(stats);
    }
  }
  clock.finish(row);
  copy_counts();
  return stats;
}

}  // namespace lptn::fw
