// The generated codecs as the firmware compiles them (-fno-exceptions -fno-rtti): pack, unpack and
// the scaling functions are constexpr, so most of this runs in the compiler.
#include <cstdint>

#include "lptn/can/lptn_frames.hpp"
#include "lptn/can/test/codec_test_frames.hpp"

namespace {

constexpr bool status_round_trips() {
  lptn::can::LptnStatus status;
  status.stale_inputs = 0x1FF;
  status.rejected_readings = 0xC3;
  status.status_counter = 5;
  std::uint8_t frame[8]{};
  lptn::can::LptnStatus decoded;
  return status.pack(frame, sizeof frame) && decoded.unpack(frame, sizeof frame) && frame[1] == 0xF5 &&
         frame[2] == 0x1F && decoded.stale_inputs == 0x1FF && decoded.rejected_readings == 0xC3;
}

constexpr bool motorola_round_trips() {
  lptn::can::test::MotMixed message;
  message.nine = -3;
  message.twelve = 0xABC;
  std::uint8_t frame[8]{};
  lptn::can::test::MotMixed decoded;
  return message.pack(frame, sizeof frame) && decoded.unpack(frame, sizeof frame) && decoded.nine == -3 &&
         decoded.twelve == 0xABC;
}

constexpr bool short_buffer_is_refused() {
  lptn::can::TcElectrical message;
  std::uint8_t frame[7]{};
  return !message.pack(frame, sizeof frame) && !message.unpack(frame, sizeof frame);
}

static_assert(status_round_trips());
static_assert(motorola_round_trips());
static_assert(short_buffer_is_refused());
static_assert(lptn::can::TcElectrical::motor_speed_encode(-16000.0) == -32000);
static_assert(lptn::can::TcElectrical::motor_speed_encode(1e300) == 32767);   // saturates
static_assert(lptn::can::TcElectrical::motor_speed_encode(0.26) == 1);        // rounds to nearest
static_assert(lptn::can::TcElectrical::motor_speed_encode(-0.25) == -1);      // halves away from zero
static_assert(lptn::can::TcElectrical::motor_speed_is_in_range(32000));
static_assert(!lptn::can::TcElectrical::motor_speed_is_in_range(32001));
static_assert(lptn::can::TcCooling::cooling_airflow_decode(60000) == 30.0);

}  // namespace

// The checks ran in the compiler; the exit code tells ctest that the program also links and runs.
int main() { return status_round_trips() && motorola_round_trips() && short_buffer_is_refused() ? 0 : 1; }
