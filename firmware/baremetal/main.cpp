// The Cortex-M7 image until the firmware's observer replaces this loop: the model stepped on the
// converter's frames, its temperatures packed into the output frame. It shows that the model and
// the generated codecs build for the MCU without heap or exceptions (tools/check-m7-image.sh).
#include <cstddef>
#include <cstdint>

#include "lptn/can/lptn_frames.hpp"
#include "lptn/model.hpp"

namespace {

// Stand-ins for the CAN controller's mailboxes. Volatile: every frame is read and every result
// written, so the compiler cannot fold the model away.
volatile std::uint8_t g_rx_electrical[8];
volatile std::uint8_t g_rx_cooling[8];
volatile std::uint8_t g_tx_temperatures[8];

void receive(const volatile std::uint8_t (&mailbox)[8], std::uint8_t (&frame)[8]) {
  for (std::size_t i = 0; i < sizeof frame; ++i) frame[i] = mailbox[i];
}

}  // namespace

int main() {
  using lptn::can::LptnTemperatures;
  using lptn::can::TcCooling;
  using lptn::can::TcElectrical;
  const lptn::Model<float> model;
  static constexpr lptn::ParamVector<float> kParams = lptn::default_params<float>();
  float x[lptn::kMaxStates];
  model.initial_state(x, 20.0f, 20.0f);
  lptn::Inputs<float> in;
  for (;;) {
    std::uint8_t frame[8];
    receive(g_rx_electrical, frame);
    if (TcElectrical m; m.unpack(frame, sizeof frame)) {
      in.speed_rpm = static_cast<float>(TcElectrical::motor_speed_decode(m.motor_speed));
      in.frequency_hz = static_cast<float>(TcElectrical::stator_frequency_decode(m.stator_frequency));
      in.current_a = static_cast<float>(TcElectrical::stator_current_decode(m.stator_current));
    }
    receive(g_rx_cooling, frame);
    if (TcCooling m; m.unpack(frame, sizeof frame)) {
      in.airflow_m3s = static_cast<float>(TcCooling::cooling_airflow_decode(m.cooling_airflow));
      in.ambient_c = static_cast<float>(TcCooling::ambient_temp_decode(m.ambient_temp));
    }
    model.step(x, in, kParams.data(), 0.1f);

    LptnTemperatures out;
    out.stator_winding_temp = LptnTemperatures::stator_winding_temp_encode(x[lptn::kStatorWinding]);
    out.stator_core_temp = LptnTemperatures::stator_core_temp_encode(x[lptn::kStatorCore]);
    out.rotor_winding_temp = LptnTemperatures::rotor_winding_temp_encode(x[lptn::kRotorWinding]);
    out.rotor_core_temp = LptnTemperatures::rotor_core_temp_encode(x[lptn::kRotorCore]);
    if (out.pack(frame, sizeof frame))
      for (std::size_t i = 0; i < sizeof frame; ++i) g_tx_temperatures[i] = frame[i];
  }
}
