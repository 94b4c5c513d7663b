#include "replay.hpp"

namespace lptn::fw {

ReplayStats replay_frames(FrameSource& log, Estimator<double>& estimator, const ReplaySinks& sinks) {
  ReplayStats stats;
  const TimeUs dt_us = static_cast<TimeUs>(estimator.config().observer.dt_s * kUsPerS + 0.5);
  TimeUs next_tick = 0;
  bool started = false;
  auto tick = [&] {
    const EstimatorOutput<double>& out = estimator.tick(next_tick);
    ++stats.ticks;
    if (out.initialized) {
      ++stats.rows;
      if (sinks.row) sinks.row(out, stats.first_us);
    }
    next_tick += dt_us;
  };

  TimeUs time_us = 0;
  CanFrame frame;
  const char* why = nullptr;
  for (FrameSource::Status status; (status = log.next(time_us, frame, why)) != FrameSource::Status::end;) {
    stats.records = log.record();
    if (status == FrameSource::Status::bad) {
      ++stats.bad_records;
      if (sinks.bad_record) sinks.bad_record(stats.records, why);
      continue;
    }
    if (!started) {
      started = true;
      next_tick = time_us;
      stats.first_us = time_us;
    }
    if (time_us - next_tick > kMaxTickedGapUs) {
      ++stats.re_anchored;
      next_tick = time_us;
    }
    while (next_tick < time_us) tick();
    estimator.receive(frame, time_us);
    if (time_us > stats.last_us) stats.last_us = time_us;
    ++stats.frames;
    if (sinks.progress && stats.frames % sinks.progress_every == 0) sinks.progress(stats);
  }
  if (started)
    while (next_tick <= stats.last_us) tick();
  return stats;
}

}  // namespace lptn::fw
