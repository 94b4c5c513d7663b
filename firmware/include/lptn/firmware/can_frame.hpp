// One CAN frame as the estimator sees it, whatever brought it (a SocketCAN socket, a candump log,
// a bare-metal driver). Fixed size: no heap.
#pragma once

#include <cstdint>

namespace lptn::fw {

struct CanFrame {
  std::uint32_t id = 0;   // 11 or 29 bits, without flags
  std::uint8_t len = 0;   // data bytes (classic CAN: 0..8; FD: up to 64)
  bool extended = false;  // 29-bit id
  bool remote = false;    // remote transmission request (no data)
  bool error = false;     // an error frame reported by the controller
  bool fd = false;        // CAN FD frame
  std::uint8_t data[64]{};
};

// A message of the DBC's generated codecs (lptn/can/lptn_frames.hpp) as a frame.
template <class Msg>
CanFrame to_frame(const Msg& m) {
  CanFrame f;
  f.id = Msg::kId;
  f.extended = Msg::kExtended;
  f.len = Msg::kLength;
  m.pack(f.data, sizeof f.data);
  return f;
}

}  // namespace lptn::fw
