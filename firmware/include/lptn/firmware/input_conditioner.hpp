// Signal conditioning: which input values may reach the model.
//
// Every input has a plausible range and a freshness timeout. A value that is not a number or lies
// outside its range never reaches the model, and neither does a frame whose alive counter froze
// or skipped (the estimator checks the counters). An input that has had no good value for longer
// than its timeout is stale: the model holds its last good value for a grace period, then runs on
// the input's conservative value, one that can only make the estimate hotter (see
// conservative_limits() in estimator_config.hpp for each value and why). Each state is reported
// in the status frame.
#pragma once

#include <cmath>

#include "lptn/firmware/input.hpp"

namespace lptn::fw {

template <class T>
struct InputLimits {
  T min = T(0), max = T(0);   // plausible range, physical units (outside: a fault, not data)
  TimeUs timeout_us = 0;      // no good value for longer than this: stale
  TimeUs grace_us = 0;        // then the last good value is held this much longer
  T conservative = T(0);      // and then this one is used (inputs the model runs on)
};

// How an input reaches the model at one instant.
enum class InputUse : std::uint8_t {
  absent,       // never had a good value (optional inputs: not on this bus)
  fresh,        // a good value within the timeout
  held,         // stale or faulty, its last good value held within the grace period
  substituted,  // beyond the grace period: the conservative value
};

template <class T>
struct InputSample {
  T value = T(0);
  InputUse use = InputUse::absent;
  bool usable() const { return use != InputUse::absent; }
};

template <class T>
class InputConditioner {
 public:
  void set_limits(Input i, const InputLimits<T>& limits) { state_[index_of(i)].limits = limits; }
  const InputLimits<T>& limits(Input i) const { return state_[index_of(i)].limits; }

  // A decoded value received at time t. Returns false if it was rejected as implausible.
  bool receive(Input i, T value, TimeUs t) {
    Channel& c = state_[index_of(i)];
    c.counter_fault = false;
    c.received = value;
    using std::isfinite;
    if (!isfinite(value) || value < c.limits.min || value > c.limits.max) {
      c.implausible = true;
      return false;
    }
    c.implausible = false;
    c.value = value;
    c.t_good = t;
    c.has_good = true;
    ++c.sequence;
    return true;
  }

  // The input's frame arrived with a frozen or skipped alive counter: its content is not trusted,
  // and the input is stale until a frame with a good counter arrives.
  void counter_fault(Input i) { state_[index_of(i)].counter_fault = true; }

  InputSample<T> sample(Input i, TimeUs now) const {
    const Channel& c = state_[index_of(i)];
    if (!c.has_good) return {c.limits.conservative, InputUse::absent};
    const TimeUs age = now > c.t_good ? now - c.t_good : 0;  // a clock that went back makes nothing older
    if (!c.counter_fault && !c.implausible && age <= c.limits.timeout_us) return {c.value, InputUse::fresh};
    if (age <= c.limits.timeout_us + c.limits.grace_us) return {c.value, InputUse::held};
    return {c.limits.conservative, InputUse::substituted};
  }

  // Stale: no good value within the timeout, or the frame's alive counter froze or skipped.
  bool stale(Input i, TimeUs now) const {
    const Channel& c = state_[index_of(i)];
    if (!c.has_good) return c.counter_fault;
    return c.counter_fault || (now > c.t_good && now - c.t_good > c.limits.timeout_us);
  }
  bool implausible(Input i) const { return state_[index_of(i)].implausible; }
  // The last value received, plausible or not (NaN: none yet): what the bus said, for a check of
  // the bus against the motor (lptn replay's against the nameplate), not for the model.
  T last_received(Input i) const { return state_[index_of(i)].received; }

  // Counts good values, so that a consumer can tell a new reading from the one it already used.
  unsigned sequence(Input i) const { return state_[index_of(i)].sequence; }

  InputMask stale_mask(TimeUs now) const {
    InputMask m = 0;
    for (int i = 0; i < kNumInputs; ++i)
      if (stale(static_cast<Input>(i), now)) m |= bit(static_cast<Input>(i));
    return m;
  }
  InputMask implausible_mask() const {
    InputMask m = 0;
    for (int i = 0; i < kNumInputs; ++i)
      if (state_[i].implausible) m |= bit(static_cast<Input>(i));
    return m;
  }

 private:
  struct Channel {
    InputLimits<T> limits;
    T value = T(0);
    T received = T(NAN);
    TimeUs t_good = 0;
    bool has_good = false;
    bool implausible = false;
    bool counter_fault = false;
    unsigned sequence = 0;
  };
  Channel state_[kNumInputs];
};

}  // namespace lptn::fw
