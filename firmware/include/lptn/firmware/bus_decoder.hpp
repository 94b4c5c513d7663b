// The converter's bus as the estimator sees it: a decoder turns a CAN frame into the inputs it
// carries. Which messages and signals those are is the bus map's (bus.toml): at build time its
// generated glue (lptn-bus-codegen, lptn/bus/bus_glue.hpp) decodes through the converter
// DBC's generated codecs; `lptn replay --bus` reads the map and the DBC at run time
// (can/bus). Both fill the same BusReading, so the estimator cannot tell them apart.
#pragma once

#include <cstdint>

#include "lptn/firmware/can_frame.hpp"
#include "lptn/firmware/input.hpp"

namespace lptn::fw {

// A CAN id the estimator sends one of its frames on: lptn.dbc's, or the bus map's [outputs].
struct OutputId {
  std::uint32_t id;
  bool extended;
};
// The estimator's frames (output_frames.hpp): temperatures, their deviations, margin, status,
// innovation, cooling.
inline constexpr int kMaxOutputFrames = 6;

// Messages of one map with an alive counter of their own (the estimator keeps one per message).
inline constexpr int kMaxBusMessages = 16;

// One frame of a message of the map.
struct BusReading {
  int message = 0;          // the message's index in the map, 0..kMaxBusMessages-1
  bool malformed = false;   // wrong length, flags or layout: nothing of it is used
  InputMask carried = 0;    // every input the message maps, also those this frame's multiplexor leaves out
  bool has_counter = false;
  std::uint8_t counter = 0;           // the alive counter's value
  std::uint16_t counter_modulo = 16;  // it counts 0..modulo-1
  std::uint8_t max_delta_counter = 1; // a jump up to this is frames lost and tolerated (AUTOSAR E2E)
  bool has_crc = false;               // the map names the message's CRC (e2e.hpp)
  bool crc_ok = true;                 // ... and the frame's is right
  int n = 0;                        // the values this frame carries
  Input input[kNumInputs]{};
  double value[kNumInputs]{};       // physical, in the input's unit

  void add(Input i, double v) noexcept {
    if (n < kNumInputs) {
      input[n] = i;
      value[n] = v;
      ++n;
    }
  }
};

// Decodes `frame` into `out` (a fresh BusReading); false if no message of the map has its id.
using BusDecodeFn = bool (*)(const void* context, const CanFrame& frame, BusReading& out);

struct BusDecoder {
  BusDecodeFn decode = nullptr;
  const void* context = nullptr;      // the run-time map's, for its decode
  std::uint32_t input_cycle_ms[kNumInputs]{};  // each input's message cycle time (0: not on this bus)
};

}  // namespace lptn::fw
