// The observer's inputs, numbered as the bits of the status frame's input masks (can/codecs/lptn.dbc,
// LPTN_Status: StaleInputs, ImplausibleInputs, SubstitutedInputs).
#pragma once

#include <cstdint>

namespace lptn::fw {

enum class Input : std::uint8_t {
  speed,
  current,
  frequency,
  airflow,
  ambient,
  torque,
  voltage,
  stator_sensor,
  rotor_sensor,
};
inline constexpr int kNumInputs = 9;

using InputMask = std::uint16_t;

constexpr int index_of(Input i) { return static_cast<int>(i); }
constexpr InputMask bit(Input i) { return static_cast<InputMask>(1u << index_of(i)); }

inline constexpr const char* kInputNames[kNumInputs] = {"speed",  "current", "frequency",     "airflow",     "ambient",
                                                        "torque", "voltage", "stator_sensor", "rotor_sensor"};
// Each input's unit, as its plausible range is given (estimator_config.hpp).
inline constexpr const char* kInputUnits[kNumInputs] = {"1/min", "A", "Hz", "m3/s", "C", "Nm", "V", "C", "C"};

// What every converter sends (docs/onboard.md, "Signal conditioning"): the model cannot run without these. Torque and voltage
// refine the loss model where the bus carries them; the temperature sensors correct and start it.
inline constexpr InputMask kRequiredInputs =
    bit(Input::speed) | bit(Input::current) | bit(Input::frequency) | bit(Input::airflow) | bit(Input::ambient);

// Microseconds on one clock: the frames' receive times and the ticks. Integer so that a replay's
// time stamps, (sec.usec) in a candump log, are taken exactly and long uptimes lose nothing.
using TimeUs = std::int64_t;
inline constexpr TimeUs kUsPerS = 1000000;

}  // namespace lptn::fw
