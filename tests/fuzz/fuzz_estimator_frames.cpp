// Fuzz target: the on-board estimator (firmware/include/lptn/firmware/estimator.hpp) with the
// default calibration compiled in, as the daemon runs it, fed any stream of frames.
//
// Input: one options byte (bit 0: open loop; bit 1: float, the bare-metal scalar, instead of
// double), then records of 12 bytes, one frame each:
//   0-1  id: below 0xE000 (most inputs) one of the ids LPTN receives; below 0xF000 one it sends
//        (its own outputs echoed); above, any standard id (low 11 bits)
//   2    kind: 0x00-0x7F a frame of 8 bytes, whose alive counter (if it has one) is set to the
//        next good value unless bit 6 is set; 0x80-0xBF a wrong length (low nibble mod 8);
//        0xC0-0xFF one of error, remote, CAN FD, extended (bits 4-5)
//   3-10 data
//   11   time to the frame after this one: 2 ms steps below 0xF0; 0xFF 10 s, 0xFE 60 s of
//        silence; 0xFD the frames' clock steps back 1 s (the ticks wait for it); others none
// The estimator ticks every 100 ms of the frames' clock, as the daemon's replay does, up to ten
// minutes in all. tests/fuzz/make_estimator_seeds.py writes seeds in this format from a candump log.
//
// After every tick: temperatures, their standard deviations and the margins are finite numbers
// once initialized (the inputs that reach the model are range-checked, so nothing a bus sends
// may make them otherwise), the status fields fit their frame, and the output frames pack.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <memory>

#include LPTN_CALIBRATION_HEADER  // firmware/CMakeLists.txt: the default calibration, as the daemon's
#include "fuzz_check.hpp"
#include "lptn/can/lptn_frames.hpp"
#include "lptn/firmware/estimator.hpp"
#include "lptn/firmware/exported_calibration.hpp"
#include "lptn/firmware/output_frames.hpp"

namespace {

using namespace lptn::fw;
using lptn::kNumNodes;
namespace can = lptn::can;

constexpr std::size_t kRecordSize = 12;
constexpr TimeUs kTick = kUsPerS / 10;
// Ten minutes: every timeout and grace period of the default configuration (the longest, the
// ambient's, 123 s) runs out within it, and it bounds the time one input may take.
constexpr long kMaxTicks = 6000;

template <class T>
const EstimatorConfig<T>& base_config() {
  static const EstimatorConfig<T> config = config_from_exported_header<T>();
  return config;
}

// Sets the frame's alive counter to the next good value for its message, through the DBC's codec.
template <class Msg>
bool set_counter(CanFrame& f, std::uint8_t& counter) {
  if (f.id != Msg::kId) return false;
  Msg m;
  m.unpack(f.data, sizeof f.data);
  m.alive_counter = counter;
  m.pack(f.data, sizeof f.data);
  counter = static_cast<std::uint8_t>((counter + 1) & 0xF);
  return true;
}

struct Counters {
  std::uint8_t next[6] = {};
  void stamp(CanFrame& f) {
    (void)(set_counter<can::TcElectrical>(f, next[0]) || set_counter<can::TcTorque>(f, next[1]) ||
           set_counter<can::TcVoltage>(f, next[2]) || set_counter<can::TcCooling>(f, next[3]) ||
           set_counter<can::TcStatorTemp>(f, next[4]) || set_counter<can::BenchRotorTemp>(f, next[5]));
  }
};

CanFrame frame_of(const std::uint8_t* r, Counters& counters) {
  CanFrame f;
  const unsigned selector = static_cast<unsigned>(r[0]) << 8 | r[1];
  if (selector < 0xE000) {
    f.id = can::kReceivedIds[selector % std::size(can::kReceivedIds)];
  } else if (selector < 0xF000) {
    f.id = can::kTransmittedIds[selector % std::size(can::kTransmittedIds)];
  } else {
    f.id = selector & 0x7FFu;
  }
  f.len = 8;
  std::memcpy(f.data, r + 3, 8);
  const std::uint8_t kind = r[2];
  if (kind < 0x80) {
    if ((kind & 0x40) == 0) counters.stamp(f);
  } else if (kind < 0xC0) {
    f.len = static_cast<std::uint8_t>((kind & 0x0F) % 8);
  } else {
    switch ((kind >> 4) & 3) {
      case 0: f.error = f.extended = true; break;
      case 1: f.remote = true; break;
      case 2: f.fd = true; break;
      default: f.extended = true; break;
    }
  }
  return f;
}

template <class T>
void check_output(const EstimatorOutput<T>& o, TimeUs t) {
  LPTN_FUZZ_CHECK(o.time_us == t, "the output's time is the tick's");
  // The signals' widths from the DBC (its generated ranges), not restated here.
  LPTN_FUZZ_CHECK(lptn::can::LptnStatus::status_counter_is_in_range(o.status_counter) &&
                      lptn::can::LptnStatus::bus_events_is_in_range(o.bus_events),
                  "status fields wider than their signals");
  constexpr InputMask kAll = (1u << kNumInputs) - 1;
  LPTN_FUZZ_CHECK((o.stale & ~kAll) == 0 && (o.implausible & ~kAll) == 0 && (o.substituted & ~kAll) == 0,
                  "input masks");
  CanFrame frames[kMaxOutputFrames];
  const int n = pack_outputs(o, frames);
  if (!o.initialized) {
    LPTN_FUZZ_CHECK(o.mode == Mode::not_initialized, "mode before the start");
    LPTN_FUZZ_CHECK(n == 1, "only the status frame before the start");
    return;
  }
  LPTN_FUZZ_CHECK(n == kMaxOutputFrames, "every output frame once started");
  LPTN_FUZZ_CHECK(o.mode != Mode::not_initialized, "mode after the start");
  for (int i = 0; i < kNumNodes; ++i) {
    LPTN_FUZZ_CHECK(std::isfinite(o.node_c[i]), "a node temperature is not a number");
    LPTN_FUZZ_CHECK(std::isfinite(o.node_std_k[i]) && o.node_std_k[i] >= 0, "a standard deviation");
  }
  LPTN_FUZZ_CHECK(o.limiting_node >= 0 && o.limiting_node < kNumNodes, "limiting node");
  LPTN_FUZZ_CHECK(std::isfinite(o.margin_k) && std::isfinite(o.margin_conservative_k), "margins");
  // The cooling state: a finite factor within the observer's clamp (1/5..5), a finite spread, and
  // an alarm only while the estimate is or was tracking.
  const double clamp = std::exp(kMaxLnCoolingFactor) * (1 + 1e-5);  // float's rounding of exp
  LPTN_FUZZ_CHECK(std::isfinite(o.cooling_factor) && double(o.cooling_factor) >= 1 / clamp &&
                      double(o.cooling_factor) <= clamp,
                  "cooling factor beyond the observer's clamp");
  LPTN_FUZZ_CHECK(std::isfinite(o.cooling_factor_std) && o.cooling_factor_std >= 0, "cooling factor's spread");
  LPTN_FUZZ_CHECK(lptn::can::LptnCooling::cooling_state_is_in_range(static_cast<std::uint8_t>(o.cooling_state)),
                  "cooling state wider than its signal");
  LPTN_FUZZ_CHECK(o.cooling_state != CoolingState::off || (!o.cooling_alarm && o.cooling_factor == T(1)),
                  "a cooling alarm or factor while the state is off");
  LPTN_FUZZ_CHECK(o.margin_conservative_k <= o.margin_k, "the conservative margin is the smaller");
}

template <class T>
void run(const std::uint8_t* data, std::size_t size, bool open_loop) {
  EstimatorConfig<T> config = base_config<T>();
  config.fuse_stator_sensor = !open_loop;
  const auto estimator = std::make_unique<Estimator<T>>(config);
  Counters counters;
  TimeUs t_frame = 0, next_tick = 0;
  long ticks = 0;
  auto tick_until = [&](TimeUs t) {
    for (; next_tick <= t && ticks < kMaxTicks; next_tick += kTick, ++ticks)
      check_output(estimator->tick(next_tick), next_tick);
  };
  for (; size >= kRecordSize && ticks < kMaxTicks; data += kRecordSize, size -= kRecordSize) {
    const CanFrame f = frame_of(data, counters);
    tick_until(t_frame);
    estimator->receive(f, t_frame);
    const std::uint8_t delta = data[11];
    if (delta < 0xF0) {
      t_frame += delta * 2000;
    } else if (delta == 0xFF) {
      t_frame += 10 * kUsPerS;
    } else if (delta == 0xFE) {
      t_frame += 60 * kUsPerS;
    } else if (delta == 0xFD) {
      t_frame -= kUsPerS;
    }
  }
  tick_until(next_tick + 10 * kTick);  // one more second after the last frame, nothing received
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const bool open_loop = (data[0] & 1) != 0;
  if (data[0] & 2) {
    run<float>(data + 1, size - 1, open_loop);
  } else {
    run<double>(data + 1, size - 1, open_loop);
  }
  return 0;
}
