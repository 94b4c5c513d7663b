// What every TD3 formulation's loop does alike with its training curve: the trailing average of
// the rewards and the report the progress callback gets.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "trainer/td3/td3_calibration.hpp"

namespace lptn::td3 {

// Appends `rec` to `curve` with its average: of its reward and the rewards of the records before
// it, `window` in all at most.
inline void append_with_average(std::vector<EpisodeRecord>& curve, EpisodeRecord rec, int window) {
  double sum = rec.reward;
  std::size_t n = 1;
  for (auto it = curve.rbegin(); it != curve.rend() && n < static_cast<std::size_t>(window); ++it, ++n) sum += it->reward;
  rec.average = sum / static_cast<double>(n);
  curve.push_back(rec);
}

// The progress report after `done` of `max` episodes (rounds), `first` of them done before this
// process started, `seconds_before` their time; the time left extrapolated from this process's pace.
inline EpisodeReport progress_report(const EpisodeRecord& rec, int done, int max, int first, double seconds,
                                     double seconds_before, bool random) {
  EpisodeReport r;
  r.episode = done;
  r.max_episodes = max;
  r.reward = rec.reward;
  r.average = rec.average;
  r.seconds = seconds;
  r.seconds_left = (seconds - seconds_before) / std::max(1, done - first) * (max - done);
  r.random = random;
  return r;
}

}  // namespace lptn::td3
