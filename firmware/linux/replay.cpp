#include "replay.hpp"

#include "hostio/line_reader.hpp"

#include <string_view>

namespace lptn::fw {

ReplayStats replay_candump(std::FILE* log, Estimator<double>& estimator, const ReplaySinks& sinks) {
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

  LineReader reader(log);
  std::string_view line;
  for (LineReader::Status status; (status = reader.next(line)) != LineReader::Status::end;) {
    ++stats.lines;
    if (status == LineReader::Status::too_long) {
      ++stats.bad_lines;
      if (sinks.bad_line) sinks.bad_line(stats.lines, "line longer than 512 bytes, not a candump line");
      continue;
    }
    if (line.empty()) continue;
    CandumpRecord rec;
    if (const char* why = parse_candump_line(line, rec)) {
      ++stats.bad_lines;
      if (sinks.bad_line) sinks.bad_line(stats.lines, why);
      continue;
    }
    if (!started) {
      started = true;
      next_tick = rec.time_us;
      stats.first_us = rec.time_us;
    }
    if (rec.time_us - next_tick > kMaxTickedGapUs) {
      ++stats.re_anchored;
      next_tick = rec.time_us;
    }
    while (next_tick < rec.time_us) tick();
    estimator.receive(rec.frame, rec.time_us);
    if (rec.time_us > stats.last_us) stats.last_us = rec.time_us;
    ++stats.frames;
    if (sinks.progress && stats.frames % sinks.progress_every == 0) sinks.progress(stats);
  }
  if (started)
    while (next_tick <= stats.last_us) tick();
  return stats;
}

}  // namespace lptn::fw
