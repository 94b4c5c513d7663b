// The Cortex-M7 image: the estimator with the exported default calibration compiled in, in float,
// on a minimal main. The CAN controller and the 100 ms timer are stand-ins (volatile mailboxes and
// a tick flag a timer interrupt would set), so the compiler keeps every path the real port needs:
// frames in through the DBC's codecs, a tick, frames out. scripts/check-m7-image.sh proves the ELF
// holds no heap and no exception code.
#include <cstddef>
#include <cstdint>

#include LPTN_CALIBRATION_HEADER  // firmware/CMakeLists.txt: an `lptn export`
#include "lptn/firmware/estimator.hpp"
#include "lptn/firmware/exported_calibration.hpp"
#include "lptn/firmware/output_frames.hpp"

namespace {

// What a CAN driver's receive interrupt would fill, and a transmit mailbox per output frame.
struct Mailbox {
  volatile std::uint32_t id;
  volatile std::uint8_t len;
  volatile std::uint8_t data[8];
  volatile bool full;
};
Mailbox g_rx[8];
Mailbox g_tx[lptn::fw::kMaxOutputFrames];
volatile bool g_tick_due = false;            // set every 100 ms by the timer interrupt
volatile lptn::fw::TimeUs g_now_us = 0;      // the free-running microsecond clock

lptn::fw::CanFrame take(Mailbox& m) {
  lptn::fw::CanFrame f;
  f.id = m.id;
  f.len = m.len > 8 ? 8 : m.len;
  for (std::size_t i = 0; i < f.len; ++i) f.data[i] = m.data[i];
  m.full = false;
  return f;
}

void put(Mailbox& m, const lptn::fw::CanFrame& f) {
  m.id = f.id;
  m.len = f.len;
  for (std::size_t i = 0; i < f.len; ++i) m.data[i] = f.data[i];
  m.full = true;
}

}  // namespace

int main() {
  // Start-up: the whole estimator lives in static storage, built once.
  static lptn::fw::Estimator<float> estimator(lptn::fw::config_from_exported_header<float>());
  lptn::fw::CanFrame out[lptn::fw::kMaxOutputFrames];
  for (;;) {
    for (Mailbox& m : g_rx)
      if (m.full) estimator.receive(take(m), g_now_us);
    if (!g_tick_due) continue;
    g_tick_due = false;
    const int n = lptn::fw::pack_outputs(estimator.tick(g_now_us), out);
    for (int i = 0; i < n; ++i) put(g_tx[i], out[i]);
  }
}
