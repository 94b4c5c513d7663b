// Whether the stator winding sensor may correct the model: the fusion gate rejects single bad
// readings; this judges the sensor as a whole. It is failed, and the observer runs open loop,
// when readings keep being rejected or when the reading stays frozen while the model says the
// winding has moved. It is trusted again after a run of readings that pass the gate and move.
#pragma once

#include <cmath>
#include <cstdint>

#include "lptn/firmware/input.hpp"

namespace lptn::fw {

// As the status frame's StatorSensorState (can/codecs/lptn.dbc).
enum class SensorState : std::uint8_t { fused = 0, rejected = 1, unavailable = 2, failed_open_loop = 3 };

template <class T>
struct SensorMonitorSettings {
  int failed_after_rejections = 30;   // consecutive gated-out readings (30 s at 1 Hz)
  TimeUs stuck_after_us = 300 * kUsPerS;  // the same reading this long...
  T stuck_model_change_k = T(3);      // ...while the model's sensor temperature moved this much
  int trusted_after_readings = 10;    // consecutive readings that pass the gate and are not frozen
};

template <class T>
class SensorMonitor {
 public:
  explicit SensorMonitor(const SensorMonitorSettings<T>& s = {}) : s_(s) {}
  void set_settings(const SensorMonitorSettings<T>& s) { s_ = s; }

  bool failed() const { return failed_; }
  // Rejected readings since start (the status frame saturates it at 255).
  std::uint32_t rejections() const { return rejections_; }

  // A new reading at time t; `model_motion` is how far the model's own steps (predictions, not
  // corrections) moved the sensor's temperature since the previous reading. Fused readings pull
  // the estimate towards a frozen value, so only the model's motion can show that it is stuck.
  // Returns true if the observer may fuse the reading.
  bool on_reading(T reading, T model_motion, bool passes_gate, TimeUs t) {
    using std::fabs;
    const bool frozen = have_last_ && reading == last_reading_;
    if (!frozen) {
      frozen_since_ = t;
      motion_while_frozen_ = T(0);
    } else {
      motion_while_frozen_ += model_motion;
    }
    have_last_ = true;
    last_reading_ = reading;
    const bool stuck = frozen && t - frozen_since_ >= s_.stuck_after_us &&
                       fabs(motion_while_frozen_) >= s_.stuck_model_change_k;

    if (failed_) {
      good_run_ = passes_gate && !stuck ? good_run_ + 1 : 0;
      if (good_run_ >= s_.trusted_after_readings) {
        failed_ = false;
        rejected_run_ = 0;
      }
      return false;
    }
    if (stuck) return fail();
    if (!passes_gate) {
      ++rejections_;
      if (++rejected_run_ >= s_.failed_after_rejections) return fail();
      return false;
    }
    rejected_run_ = 0;
    return true;
  }

 private:
  bool fail() {
    failed_ = true;
    good_run_ = 0;
    return false;
  }

  SensorMonitorSettings<T> s_;
  bool failed_ = false;
  bool have_last_ = false;
  T last_reading_ = T(0);
  TimeUs frozen_since_ = 0;
  T motion_while_frozen_ = T(0);
  int rejected_run_ = 0;
  int good_run_ = 0;
  std::uint32_t rejections_ = 0;
};

}  // namespace lptn::fw
