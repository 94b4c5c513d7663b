// End-to-end protection of CAN frames, in the manner of AUTOSAR E2E profiles 1 and 2: each
// protected frame carries a 4-bit counter (+1 per frame sent) and a CRC-8 over its data id and
// every byte of the frame but the CRC's own. A receiver drops a frame whose CRC fails, or whose
// counter repeated or jumped by more than MaxDeltaCounter; it tolerates lost frames up to that.
//
// The CRC is CRC-8 SAE J1850 (polynomial 0x1D, initial value 0xFF, final XOR 0xFF; check value
// 0x4B over "123456789"), run over the data id's low byte, its high byte, then the frame's bytes
// in order, skipping the CRC byte. The data id is a 16-bit number both ends agree on: for lptn's
// own frames (can/codecs/lptn.dbc) the message's DBC id, whatever CAN id it is sent with.
// No heap, no exceptions, no table: a bitwise loop (at most 66 bytes a frame).
#pragma once

#include <cstdint>

namespace lptn::fw::e2e {

constexpr std::uint8_t crc8_j1850_update(std::uint8_t crc, std::uint8_t byte) {
  crc = static_cast<std::uint8_t>(crc ^ byte);
  for (int bit = 0; bit < 8; ++bit)
    crc = static_cast<std::uint8_t>((crc & 0x80u) ? ((crc << 1) ^ 0x1Du) : (crc << 1));
  return crc;
}

// CRC-8 SAE J1850 of n bytes.
constexpr std::uint8_t crc8_j1850(const std::uint8_t* data, int n) {
  std::uint8_t crc = 0xFF;
  for (int i = 0; i < n; ++i) crc = crc8_j1850_update(crc, data[i]);
  return static_cast<std::uint8_t>(crc ^ 0xFFu);
}

// The CRC a frame of `len` bytes must carry in byte `crc_byte`, for `data_id`.
constexpr std::uint8_t frame_crc(std::uint16_t data_id, const std::uint8_t* data, int len, int crc_byte) {
  std::uint8_t crc = 0xFF;
  crc = crc8_j1850_update(crc, static_cast<std::uint8_t>(data_id & 0xFFu));
  crc = crc8_j1850_update(crc, static_cast<std::uint8_t>(data_id >> 8));
  for (int i = 0; i < len; ++i)
    if (i != crc_byte) crc = crc8_j1850_update(crc, data[i]);
  return static_cast<std::uint8_t>(crc ^ 0xFFu);
}

// How a counter moved from the last accepted frame: AUTOSAR's E2E_P01 states, reduced to what a
// receiver acts on.
enum class CounterCheck : std::uint8_t {
  first,     // no frame before: accepted
  ok,        // +1
  lost,      // +2..+max_delta: frames lost in between, accepted
  repeated,  // +0: the same frame again (a frozen sender, a replay), dropped
  jumped,    // beyond max_delta: too many lost (or out of order), dropped
};

// Alive counter of one message, counting 0..modulo-1.
struct CounterState {
  bool seen = false;
  std::uint8_t last = 0;

  CounterCheck step(std::uint8_t c, unsigned modulo, unsigned max_delta) {
    if (!seen) {
      seen = true;
      last = c;
      return CounterCheck::first;
    }
    const unsigned delta = (static_cast<unsigned>(c) + modulo - last) % modulo;
    if (delta == 0) return CounterCheck::repeated;
    last = c;  // resynchronise on a jump: the next frame in sequence is good again
    if (delta == 1) return CounterCheck::ok;
    return delta <= max_delta ? CounterCheck::lost : CounterCheck::jumped;
  }
};

}  // namespace lptn::fw::e2e
