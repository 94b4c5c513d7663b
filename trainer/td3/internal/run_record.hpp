// What every TD3 formulation's loop does alike: the run's state between rounds or episodes (what a
// checkpoint holds besides the agent, and what the outcome takes from it), the trailing average of
// the rewards and the report the progress callback gets.
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
#include <random>
#include <vector>

#include "trainer/td3/td3_calibration.hpp"

namespace lptn::td3 {

// The run's state between rounds (the sequential formulation) or episodes (the paper's two).
struct RunState {
  int done = 0;  // rounds or episodes done
  std::mt19937_64 rng;
  std::vector<EpisodeRecord> curve;
  double initial_evaluation = 0;
  // The constant set that fit the training cycles best so far (the starting guess until one does
  // better), its training RMSE (stator and rotor pooled) and the round or episode it came at.
  ParamVector<double> best{};
  double best_train_rmse_k = std::numeric_limits<double>::infinity();
  int best_at = 0;
  double seconds = 0;
  std::size_t simulated_steps = 0;  // model steps, offsets' fits and scores included
  long long updates = 0;            // gradient steps
};

// What the outcome of every formulation takes from its run state.
inline void take_run_state(const RunState& s, Td3Outcome& out) {
  out.values = s.best;
  out.best_episode = s.best_at;
  out.best_train_rmse_k = s.best_train_rmse_k;
  out.curve = s.curve;
  out.initial_evaluation = s.initial_evaluation;
  out.episodes = s.done;
  out.seconds = s.seconds;
  out.simulated_steps = s.simulated_steps;
  out.updates = s.updates;
}

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
