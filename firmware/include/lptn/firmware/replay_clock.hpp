// How a log's time stamps drive the estimator's ticks in a replay: ticks every dt from the first
// frame's time, the frames at or before a tick's time reach the estimator first; a forward jump
// longer than kMaxTickedGapUs is not ticked through (the ticks restart at the next frame). One
// place for `lptn replay` and `lptn-daemon --replay` (firmware/linux/replay.cpp) and the bare-metal
// replay image (firmware/baremetal), so they differ only in where the frames come from. No heap.
#pragma once

#include <cstddef>

#include "lptn/firmware/can_frame.hpp"
#include "lptn/firmware/estimator.hpp"
#include "lptn/firmware/input.hpp"

namespace lptn::fw {

inline constexpr TimeUs kMaxTickedGapUs = 3600 * kUsPerS;

struct ReplayCounts {
  std::size_t frames = 0;       // handed to the estimator
  std::size_t ticks = 0;
  std::size_t rows = 0;         // ticks with an initialized estimate
  std::size_t re_anchored = 0;  // forward jumps too long to tick through
  TimeUs first_us = 0, last_us = 0;
};

template <class S>
class ReplayClock {
 public:
  explicit ReplayClock(Estimator<S>& estimator)
      : estimator_(estimator), dt_us_(static_cast<TimeUs>(estimator.config().observer.dt_s * kUsPerS + 0.5)) {}

  // A frame at time_us: the ticks due before it, then the frame. on_row(output, first_us) for
  // every tick with an initialized estimate.
  template <class OnRow>
  void frame(TimeUs time_us, const CanFrame& f, OnRow&& on_row) {
    if (!started_) {
      started_ = true;
      next_tick_ = time_us;
      counts_.first_us = time_us;
    }
    if (time_us - next_tick_ > kMaxTickedGapUs) {
      ++counts_.re_anchored;
      next_tick_ = time_us;
    }
    while (next_tick_ < time_us) tick(on_row);
    estimator_.receive(f, time_us);
    if (time_us > counts_.last_us) counts_.last_us = time_us;
    ++counts_.frames;
  }

  // The ticks up to the last frame's time.
  template <class OnRow>
  void finish(OnRow&& on_row) {
    if (started_)
      while (next_tick_ <= counts_.last_us) tick(on_row);
  }

  const ReplayCounts& counts() const { return counts_; }

 private:
  template <class OnRow>
  void tick(OnRow& on_row) {
    const EstimatorOutput<S>& out = estimator_.tick(next_tick_);
    ++counts_.ticks;
    if (out.initialized) {
      ++counts_.rows;
      on_row(out, counts_.first_us);
    }
    next_tick_ += dt_us_;
  }

  Estimator<S>& estimator_;
  TimeUs dt_us_;
  TimeUs next_tick_ = 0;
  bool started_ = false;
  ReplayCounts counts_;
};

}  // namespace lptn::fw
