// The cooling alarm: the drive controller's "cooling 30 % below nominal" before the winding is at
// risk. Raised only when the estimate is sure of it, cleared only once the estimate is back well
// above, so that a factor hovering near the threshold does not chatter on the bus:
//   raise  when factor + confidence_sigma * std < raise_below   (sure the cooling is that weak)
//   clear  when factor > clear_above                             (the hysteresis band above it)
// While the estimate is frozen (no stator reading fused) the alarm holds its state.
#pragma once

namespace lptn::fw {

template <class T>
struct CoolingAlarmSettings {
  T raise_below = T(0.8);   // 20 % below the calibrated cooling
  T clear_above = T(0.85);  // 5 points of hysteresis
  T confidence_sigma = T(2);
};

// How the cooling factor is estimated this tick (as LPTN_Cooling's CoolingState).
enum class CoolingState : unsigned char { tracking = 0, frozen = 1, off = 2 };

template <class T>
class CoolingAlarm {
 public:
  explicit CoolingAlarm(const CoolingAlarmSettings<T>& s = {}) : settings_(s) {}

  bool update(T factor, T factor_std, CoolingState state) {
    if (state != CoolingState::tracking) return raised_;
    if (!raised_ && factor + settings_.confidence_sigma * factor_std < settings_.raise_below) raised_ = true;
    if (raised_ && factor > settings_.clear_above) raised_ = false;
    return raised_;
  }

 private:
  CoolingAlarmSettings<T> settings_;
  bool raised_ = false;
};

}  // namespace lptn::fw
