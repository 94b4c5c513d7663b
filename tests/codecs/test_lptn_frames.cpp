// The codecs generated from can/codecs/lptn.dbc: frames computed by hand, every message against the
// reference layout and its DBC scaling, and the ids the LPTN node receives and sends.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "codec_checks.hpp"
#include "lptn/can/lptn_frames.hpp"

namespace {

using namespace lptn::can;
using checks::Frame;
using checks::check_message;

std::vector<std::uint8_t> packed(const auto& message) {
  Frame frame{};
  EXPECT_TRUE(message.pack(frame.data(), frame.size()));
  return {frame.begin(), frame.begin() + message.kLength};
}

TEST(LptnFrames, TcElectricalPacksLittleEndianSignedAndUnsigned) {
  TcElectrical message;
  message.motor_speed = TcElectrical::motor_speed_encode(-1.0);  // -1 rpm / 0.5 = -2 = 0xFFFE
  message.stator_frequency = TcElectrical::stator_frequency_encode(12.34);  // 1234 = 0x04D2
  message.stator_current = TcElectrical::stator_current_encode(3000.0);  // 60000 = 0xEA60
  message.pulses_enabled = 1;  // bit 48: byte 6 bit 0
  message.alive_counter = 0xA;  // bits 60..63: byte 7 bits 4..7 = 0xA0
  EXPECT_EQ(message.motor_speed, -2);
  EXPECT_EQ(message.stator_frequency, 1234);
  EXPECT_EQ(message.stator_current, 60000);
  // Little-endian: the low byte first.
  const std::vector<std::uint8_t> expected{0xFE, 0xFF, 0xD2, 0x04, 0x60, 0xEA, 0x01, 0xA0};
  EXPECT_EQ(packed(message), expected);

  TcElectrical decoded;
  ASSERT_TRUE(decoded.unpack(expected.data(), expected.size()));
  EXPECT_EQ(decoded.motor_speed, -2);  // sign-extended from 0xFFFE
  EXPECT_DOUBLE_EQ(TcElectrical::motor_speed_decode(decoded.motor_speed), -1.0);
  EXPECT_DOUBLE_EQ(TcElectrical::stator_frequency_decode(decoded.stator_frequency), 12.34);
  EXPECT_DOUBLE_EQ(TcElectrical::stator_current_decode(decoded.stator_current), 3000.0);
  EXPECT_EQ(decoded.pulses_enabled, 1);
  EXPECT_EQ(decoded.alive_counter, 0xA);
}

TEST(LptnFrames, LptnStatusPacksFieldsThatCrossBytes) {
  LptnStatus message;
  message.crc = 0x3C;                  // bits 0..7
  message.status_counter = 5;          // bits 8..11
  message.stale_inputs = 0x1FF;        // bits 12..20
  message.implausible_inputs = 0x0AA;  // bits 21..29
  message.substituted_inputs = 0x155;  // bits 30..38
  message.stator_sensor_state = static_cast<std::uint8_t>(LptnStatus::StatorSensorState::unavailable);  // 2, bits 39..40
  message.mode = static_cast<std::uint8_t>(LptnStatus::Mode::degraded);  // 1, bits 41..42
  message.torque_route_active = 1;     // bit 43
  message.voltage_route_active = 0;    // bit 44
  message.actor_scheduling = 1;        // bit 45
  message.rejected_readings = 0xC3;    // bits 46..53
  message.bus_events = 0x55;           // bits 54..60
  const std::vector<std::uint8_t> expected{
      0x3C,  // crc
      0xF5,  // counter 5 | stale bits 0..3 (0xF) << 4
      0x5F,  // stale bits 4..8 (0x1F) | implausible bits 0..2 (0x2) << 5 = 0x1F | 0x40
      0x55,  // implausible bits 3..8 (0xAA >> 3 = 0x15) | substituted bits 0..1 (0x1) << 6 = 0x15 | 0x40
      0x55,  // substituted bits 2..8 (0x155 >> 2 = 0x55) | state bit 0 (0) << 7
      0xEB,  // state bit 1 (1) | mode 1 << 1 | torque 1 << 3 | voltage 0 | actor 1 << 5 | rejected bits 0..1 (3) << 6
      0x70,  // rejected bits 2..7 (0xC3 >> 2 = 0x30) | bus events bits 0..1 (0x55 & 3 = 1) << 6 = 0x30 | 0x40
      0x15,  // bus events bits 2..6 (0x55 >> 2 = 0x15)
  };
  EXPECT_EQ(packed(message), expected);

  LptnStatus decoded;
  ASSERT_TRUE(decoded.unpack(expected.data(), expected.size()));
  EXPECT_EQ(decoded.crc, 0x3C);
  EXPECT_EQ(decoded.stale_inputs, 0x1FF);
  EXPECT_EQ(decoded.implausible_inputs, 0x0AA);
  EXPECT_EQ(decoded.substituted_inputs, 0x155);
  EXPECT_EQ(decoded.stator_sensor_state, 2);
  EXPECT_EQ(decoded.mode, 1);
  EXPECT_EQ(decoded.rejected_readings, 0xC3);
  EXPECT_EQ(decoded.bus_events, 0x55);
  EXPECT_EQ(decoded.status_counter, 5);
}

TEST(LptnFrames, TemperaturesAreOffsetUnsigned13BitFields) {
  LptnTemperatures message;
  message.crc = 0x3C;
  message.counter = 7;
  message.stator_winding_temp = LptnTemperatures::stator_winding_temp_encode(-60.0);  // (-60 + 60) / 0.05 = 0
  message.rotor_core_temp = LptnTemperatures::rotor_core_temp_encode(320.0);  // (320 + 60) / 0.05 = 7600 = 0x1DB0
  EXPECT_EQ(message.rotor_core_temp, 7600);
  // 7600 << 51: bits 51..63, i.e. byte 6 bits 3..7 (0x1DB0 & 0x1F = 0x10 -> 0x80), byte 7 (0x1DB0 >> 5 = 0xED)
  const std::vector<std::uint8_t> expected{0x3C, 0x07, 0x00, 0x00, 0x00, 0x00, 0x80, 0xED};
  EXPECT_EQ(packed(message), expected);
  EXPECT_DOUBLE_EQ(LptnTemperatures::rotor_core_temp_decode(message.rotor_core_temp), 320.0);
  EXPECT_EQ(LptnTemperatures::stator_winding_temp_encode(400.0), 8191) << "saturates at the 13-bit field (349.55 C)";
}

TEST(LptnFrames, EncodeRoundsToNearestWithHalvesAwayFromZero) {
  // MotorSpeed: 0.5 rpm per bit, so 0.25 rpm is exactly half a step.
  EXPECT_EQ(TcElectrical::motor_speed_encode(0.25), 1);
  EXPECT_EQ(TcElectrical::motor_speed_encode(-0.25), -1);
  EXPECT_EQ(TcElectrical::motor_speed_encode(0.24), 0);
  EXPECT_EQ(TcElectrical::motor_speed_encode(-0.24), 0);
  EXPECT_EQ(TcElectrical::motor_speed_encode(0.76), 2);
  EXPECT_EQ(TcElectrical::motor_speed_encode(-0.76), -2);
  EXPECT_EQ(TcElectrical::stator_current_encode(0.025), 1);  // unsigned: 0.05 A per bit
  EXPECT_EQ(TcElectrical::stator_current_encode(0.024), 0);
  EXPECT_EQ(TcElectrical::stator_current_encode(-0.5), 0);   // below the raw range
}

TEST(LptnFrames, ConstantsComeFromTheDbc) {
  static_assert(TcElectrical::kId == 0x101 && !TcElectrical::kExtended && TcElectrical::kLength == 8);
  static_assert(TcCooling::kCycleTimeMs == 1000 && LptnStatus::kCycleTimeMs == 100);
  EXPECT_EQ(std::string_view(LptnStatus::kName), "LPTN_Status");
  EXPECT_EQ(std::string_view(LptnStatus::kSender), "LPTN");
  EXPECT_EQ(std::string_view(BenchRotorTemp::kSender), "BENCH");

  const SignalInfo& speed = TcElectrical::kSignals[0];
  EXPECT_EQ(std::string_view(speed.name), "MotorSpeed");
  EXPECT_EQ(std::string_view(speed.unit), "rpm");
  EXPECT_EQ(speed.factor, 0.5);
  EXPECT_EQ(speed.offset, 0.0);
  EXPECT_EQ(speed.min, -16000.0);
  EXPECT_EQ(speed.max, 16000.0);
  EXPECT_EQ(speed.start, 0);
  EXPECT_EQ(speed.length, 16);
  EXPECT_TRUE(speed.is_signed);
  EXPECT_FALSE(speed.big_endian);
  EXPECT_EQ(std::string_view(TcCooling::kSignals[0].unit), "m3/s");
  EXPECT_EQ(std::string_view(LptnStatus::kSignals[1].name), "StatusCounter");  // DBC order
  EXPECT_EQ(LptnStatus::kNumSignals, 12u);
  static_assert(TcElectrical::kNumSignals == 5);
}

TEST(LptnFrames, ValueTablesBecomeEnums) {
  static_assert(static_cast<int>(LptnStatus::StatorSensorState::fused) == 0);
  static_assert(static_cast<int>(LptnStatus::StatorSensorState::failed_open_loop) == 3);
  static_assert(static_cast<int>(LptnStatus::Mode::not_initialized) == 3);
  static_assert(static_cast<int>(LptnMargin::LimitingNode::rotor_core) == 3);
  static_assert(std::is_same_v<std::underlying_type_t<LptnStatus::Mode>, std::uint8_t>);
}

TEST(LptnFrames, LptnReceivesTheConverterAndBenchFramesAndSendsItsOwn) {
  const std::vector<std::uint32_t> received(std::begin(kReceivedIds), std::end(kReceivedIds));
  const std::vector<std::uint32_t> transmitted(std::begin(kTransmittedIds), std::end(kTransmittedIds));
  EXPECT_EQ(received, (std::vector<std::uint32_t>{0x101, 0x102, 0x103, 0x120, 0x130, 0x131}));
  EXPECT_EQ(transmitted, (std::vector<std::uint32_t>{0x200, 0x201, 0x202, 0x203, 0x204, 0x205}));
}

// Every message: layout against the reference model, round trips, short buffers, scaling.
TEST(LptnFramesEveryMessage, TcElectrical) {
  check_message(LPTN_CAN_SIGNAL(TcElectrical, motor_speed), LPTN_CAN_SIGNAL(TcElectrical, stator_frequency),
                LPTN_CAN_SIGNAL(TcElectrical, stator_current), LPTN_CAN_SIGNAL(TcElectrical, pulses_enabled),
                LPTN_CAN_SIGNAL(TcElectrical, alive_counter));
}

TEST(LptnFramesEveryMessage, TcTorque) {
  check_message(LPTN_CAN_SIGNAL(TcTorque, motor_torque), LPTN_CAN_SIGNAL(TcTorque, alive_counter));
}

TEST(LptnFramesEveryMessage, TcVoltage) {
  check_message(LPTN_CAN_SIGNAL(TcVoltage, stator_voltage), LPTN_CAN_SIGNAL(TcVoltage, alive_counter));
}

TEST(LptnFramesEveryMessage, TcCooling) {
  check_message(LPTN_CAN_SIGNAL(TcCooling, cooling_airflow), LPTN_CAN_SIGNAL(TcCooling, ambient_temp),
                LPTN_CAN_SIGNAL(TcCooling, alive_counter));
}

TEST(LptnFramesEveryMessage, TcStatorTemp) {
  check_message(LPTN_CAN_SIGNAL(TcStatorTemp, stator_winding_temp), LPTN_CAN_SIGNAL(TcStatorTemp, alive_counter));
}

TEST(LptnFramesEveryMessage, BenchRotorTemp) {
  check_message(LPTN_CAN_SIGNAL(BenchRotorTemp, rotor_temp), LPTN_CAN_SIGNAL(BenchRotorTemp, alive_counter));
}

TEST(LptnFramesEveryMessage, LptnTemperatures) {
  check_message(LPTN_CAN_SIGNAL(LptnTemperatures, crc), LPTN_CAN_SIGNAL(LptnTemperatures, counter),
                LPTN_CAN_SIGNAL(LptnTemperatures, stator_winding_temp),
                LPTN_CAN_SIGNAL(LptnTemperatures, stator_core_temp),
                LPTN_CAN_SIGNAL(LptnTemperatures, rotor_winding_temp),
                LPTN_CAN_SIGNAL(LptnTemperatures, rotor_core_temp));
}

TEST(LptnFramesEveryMessage, LptnTemperatureStd) {
  check_message(LPTN_CAN_SIGNAL(LptnTemperatureStd, crc), LPTN_CAN_SIGNAL(LptnTemperatureStd, counter),
                LPTN_CAN_SIGNAL(LptnTemperatureStd, stator_winding_std),
                LPTN_CAN_SIGNAL(LptnTemperatureStd, stator_core_std),
                LPTN_CAN_SIGNAL(LptnTemperatureStd, rotor_winding_std),
                LPTN_CAN_SIGNAL(LptnTemperatureStd, rotor_core_std));
}

TEST(LptnFramesEveryMessage, LptnMargin) {
  check_message(LPTN_CAN_SIGNAL(LptnMargin, crc), LPTN_CAN_SIGNAL(LptnMargin, counter),
                LPTN_CAN_SIGNAL(LptnMargin, limiting_node), LPTN_CAN_SIGNAL(LptnMargin, margin),
                LPTN_CAN_SIGNAL(LptnMargin, margin_conservative), LPTN_CAN_SIGNAL(LptnMargin, limiting_node_limit));
}

TEST(LptnFramesEveryMessage, LptnStatus) {
  check_message(LPTN_CAN_SIGNAL(LptnStatus, crc), LPTN_CAN_SIGNAL(LptnStatus, status_counter),
                LPTN_CAN_SIGNAL(LptnStatus, stale_inputs), LPTN_CAN_SIGNAL(LptnStatus, implausible_inputs),
                LPTN_CAN_SIGNAL(LptnStatus, substituted_inputs), LPTN_CAN_SIGNAL(LptnStatus, stator_sensor_state),
                LPTN_CAN_SIGNAL(LptnStatus, mode), LPTN_CAN_SIGNAL(LptnStatus, torque_route_active),
                LPTN_CAN_SIGNAL(LptnStatus, voltage_route_active), LPTN_CAN_SIGNAL(LptnStatus, actor_scheduling),
                LPTN_CAN_SIGNAL(LptnStatus, rejected_readings), LPTN_CAN_SIGNAL(LptnStatus, bus_events));
}

TEST(LptnFramesEveryMessage, LptnInnovation) {
  check_message(LPTN_CAN_SIGNAL(LptnInnovation, crc), LPTN_CAN_SIGNAL(LptnInnovation, counter),
                LPTN_CAN_SIGNAL(LptnInnovation, innovation), LPTN_CAN_SIGNAL(LptnInnovation, innovation_std),
                LPTN_CAN_SIGNAL(LptnInnovation, test_ratio), LPTN_CAN_SIGNAL(LptnInnovation, observer_ticks));
}

TEST(LptnFramesEveryMessage, LptnCooling) {
  check_message(LPTN_CAN_SIGNAL(LptnCooling, crc), LPTN_CAN_SIGNAL(LptnCooling, counter),
                LPTN_CAN_SIGNAL(LptnCooling, cooling_factor), LPTN_CAN_SIGNAL(LptnCooling, cooling_factor_std),
                LPTN_CAN_SIGNAL(LptnCooling, cooling_state), LPTN_CAN_SIGNAL(LptnCooling, cooling_alarm));
}

}  // namespace
