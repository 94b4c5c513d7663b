// The generator on what lptn.dbc does not use (tests/codecs/codec_test.dbc): Motorola signals at odd
// start bits, 1- to 64-bit lengths, an extended id, a negative factor. Frames computed by hand, and
// every message against the reference layout model over random values.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "codec_checks.hpp"
#include "lptn/can/test/codec_test_frames.hpp"

namespace {

using namespace lptn::can::test;
using lptn::can::checks::Frame;
using lptn::can::checks::check_message;

std::vector<std::uint8_t> packed(const auto& message) {
  Frame frame{};
  EXPECT_TRUE(message.pack(frame.data(), frame.size()));
  return {frame.begin(), frame.begin() + message.kLength};
}

// Motorola start bits name the MSB in DBC's sawtooth numbering: byte 0 holds bits 7..0, byte 1
// bits 15..8, and a signal runs from its start bit down to bit 0 of the byte, then on from bit 7
// of the next byte.
TEST(CodecLayout, MotorolaSignalsAtOddStartBitsAndAcrossBytes) {
  MotMixed message;
  message.flag = 1;         // 7|1:   byte 0 bit 7                          -> 0x80
  message.nibble = 0xA;     // 6|4:   byte 0 bits 6..3 = 1010               -> 0x50
  message.nine = -3;        // 2|9:   0x1FD = 1 1111 1101: bits 8..6 (111) in byte 0 bits 2..0 -> 0x07,
                            //        bits 5..0 (111101) in byte 1 bits 7..2 -> 0xF4
  message.twelve = 0xABC;   // 9|12:  1010 1011 1100: bits 11..10 (10) in byte 1 bits 1..0 -> 0x02,
                            //        bits 9..2 (1010 1111) = byte 2 -> 0xAF, bits 1..0 (00) in byte 3 bits 7..6
  message.small = -16;      // 29|5:  1 0000 in byte 3 bits 5..1            -> 0x20
  message.scaled = 0x1234;  // 39|16: byte 4 = 0x12 (MSB), byte 5 = 0x34
  message.tail = 0x9A5;     // 55|12: bits 11..4 = byte 6 = 0x9A, bits 3..0 (0101) in byte 7 bits 7..4 -> 0x50
  const std::vector<std::uint8_t> expected{0x80 | 0x50 | 0x07, 0xF4 | 0x02, 0xAF, 0x20, 0x12, 0x34, 0x9A, 0x50};
  EXPECT_EQ(packed(message), expected);  // D7 F6 AF 20 12 34 9A 50

  MotMixed decoded;
  ASSERT_TRUE(decoded.unpack(expected.data(), expected.size()));
  EXPECT_EQ(decoded.flag, 1);
  EXPECT_EQ(decoded.nibble, 0xA);
  EXPECT_EQ(decoded.nine, -3);
  EXPECT_EQ(decoded.twelve, 0xABC);
  EXPECT_EQ(decoded.small, -16);
  EXPECT_EQ(decoded.scaled, 0x1234);
  EXPECT_EQ(decoded.tail, 0x9A5);
  EXPECT_DOUBLE_EQ(MotMixed::scaled_decode(decoded.scaled), 4660 * 0.25 - 10);  // (0.25,-10)
  EXPECT_DOUBLE_EQ(MotMixed::tail_decode(decoded.tail), 2469 * 0.5 + 100);      // (0.5,100)
}

TEST(CodecLayout, SixtyFourBitSignalsInBothByteOrders) {
  MotWide motorola;
  motorola.whole = 0x0123456789ABCDEF;  // 7|64@0+: the MSB first
  EXPECT_EQ(packed(motorola), (std::vector<std::uint8_t>{0x01, 0x23, 0x45, 0x67, 0x89, 0xAB, 0xCD, 0xEF}));

  IntelWide intel;
  intel.whole = -0x7FFFFFFFFFFFFFFF;  // 0|64@1-: 0x8000000000000001, the LSB first
  const std::vector<std::uint8_t> expected{0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80};
  EXPECT_EQ(packed(intel), expected);
  IntelWide decoded;
  ASSERT_TRUE(decoded.unpack(expected.data(), expected.size()));
  EXPECT_EQ(decoded.whole, -0x7FFFFFFFFFFFFFFF);

  EXPECT_EQ(MotWide::whole_encode(1e30), 0xFFFFFFFFFFFFFFFFu);
  EXPECT_EQ(IntelWide::whole_encode(-1e30), INT64_MIN);
  EXPECT_EQ(IntelWide::whole_encode(1e30), INT64_MAX);
}

TEST(CodecLayout, ExtendedIdAndOddLittleEndianLengths) {
  static_assert(ExtIntel::kId == 0x18FEF1A0 && ExtIntel::kExtended && ExtIntel::kLength == 5);
  static_assert(!MotMixed::kExtended);
  ExtIntel message;
  message.one = 1;         // 3|1:   byte 0 bit 3                      -> 0x08
  message.four = -3;       // 4|4:   1101 in byte 0 bits 4..7          -> 0xD0
  message.nine = 0x1A5;    // 13|9:  1 1010 0101: bits 0..2 (101) in byte 1 bits 5..7 -> 0xA0,
                           //        bits 3..8 (110100) in byte 2 bits 0..5 -> 0x34
  message.twelve = ExtIntel::twelve_encode(-100.0);  // 22|12 (0.1): -1000 = 0xC18 = 1100 0001 1000:
                           //        bits 0..1 (00) in byte 2 bits 6..7, bits 2..9 = byte 3 = 0x06,
                           //        bits 10..11 (11) in byte 4 bits 0..1 -> 0x03
  message.gear = static_cast<std::int8_t>(ExtIntel::Gear::reverse_fast);  // 34|3: -2 = 110 in byte 4 bits 2..4 -> 0x18
  EXPECT_EQ(message.twelve, -1000);
  const std::vector<std::uint8_t> expected{0x08 | 0xD0, 0xA0, 0x34, 0x06, 0x03 | 0x18};
  EXPECT_EQ(packed(message), expected);  // D8 A0 34 06 1B

  ExtIntel decoded;
  ASSERT_TRUE(decoded.unpack(expected.data(), expected.size()));
  EXPECT_EQ(decoded.four, -3);
  EXPECT_EQ(decoded.nine, 0x1A5);
  EXPECT_EQ(decoded.twelve, -1000);
  EXPECT_EQ(decoded.gear, -2);
  EXPECT_DOUBLE_EQ(ExtIntel::twelve_decode(decoded.twelve), -100.0);
}

TEST(CodecLayout, NegativeFactorAndOffset) {
  // (-0.5,10): raw = (value - 10) / -0.5, so -50 K is raw 120 and 5 K raw 10; [-50|5] is raw 10..120.
  EXPECT_EQ(NegFactor::inverted_encode(-50.0), 120);
  EXPECT_EQ(NegFactor::inverted_encode(5.0), 10);
  EXPECT_TRUE(NegFactor::inverted_is_in_range(10));
  EXPECT_TRUE(NegFactor::inverted_is_in_range(120));
  EXPECT_FALSE(NegFactor::inverted_is_in_range(9));
  EXPECT_FALSE(NegFactor::inverted_is_in_range(121));
  NegFactor message;
  message.inverted = 120;
  message.unranged = -3;
  EXPECT_EQ(packed(message), (std::vector<std::uint8_t>{0x78, 0xFD}));
}

TEST(CodecLayout, DbcDetailsReachTheHeader) {
  static_assert(MotMixed::kCycleTimeMs == 10);  // BA_
  static_assert(MotWide::kCycleTimeMs == 20);   // BA_DEF_DEF_
  EXPECT_EQ(std::string_view(MotMixed::kSignals[5].unit), "\xC2\xB0""C");  // the DBC's UTF-8 degree sign
  static_assert(static_cast<int>(ExtIntel::Gear::reverse) == -1);
  static_assert(static_cast<int>(ExtIntel::Gear::reserved_2) == 2);  // repeated descriptions get their value
  static_assert(static_cast<int>(ExtIntel::Gear::reserved_3) == 3);
  static_assert(std::is_same_v<std::underlying_type_t<ExtIntel::Gear>, std::int8_t>);
  static_assert(static_cast<int>(MotMixed::Flag::on) == 1);
}

TEST(CodecLayout, NodeIdsFollowReceiversSendersAndBoTxBu) {
  const std::vector<std::uint32_t> received(std::begin(kReceivedIds), std::end(kReceivedIds));
  const std::vector<std::uint32_t> transmitted(std::begin(kTransmittedIds), std::end(kTransmittedIds));
  // EXT_Intel counts as received although one of its signals (One) is for PEER alone.
  EXPECT_EQ(received, (std::vector<std::uint32_t>{0x125, 0x18FEF1A0}));
  // INTEL_Wide is PEER's, but BO_TX_BU_ lists TESTER as a transmitter too.
  EXPECT_EQ(transmitted, (std::vector<std::uint32_t>{0x123, 0x124, 0x125, 0x126}));
}

TEST(CodecLayoutEveryMessage, MotMixed) {
  check_message(LPTN_CAN_SIGNAL(MotMixed, flag), LPTN_CAN_SIGNAL(MotMixed, nibble), LPTN_CAN_SIGNAL(MotMixed, nine),
                LPTN_CAN_SIGNAL(MotMixed, twelve), LPTN_CAN_SIGNAL(MotMixed, small), LPTN_CAN_SIGNAL(MotMixed, scaled),
                LPTN_CAN_SIGNAL(MotMixed, tail));
}

TEST(CodecLayoutEveryMessage, MotWide) { check_message(LPTN_CAN_SIGNAL(MotWide, whole)); }

TEST(CodecLayoutEveryMessage, IntelWide) { check_message(LPTN_CAN_SIGNAL(IntelWide, whole)); }

TEST(CodecLayoutEveryMessage, ExtIntel) {
  check_message(LPTN_CAN_SIGNAL(ExtIntel, one), LPTN_CAN_SIGNAL(ExtIntel, four), LPTN_CAN_SIGNAL(ExtIntel, nine),
                LPTN_CAN_SIGNAL(ExtIntel, twelve), LPTN_CAN_SIGNAL(ExtIntel, gear));
}

TEST(CodecLayoutEveryMessage, NegFactor) {
  check_message(LPTN_CAN_SIGNAL(NegFactor, inverted), LPTN_CAN_SIGNAL(NegFactor, unranged));
}

}  // namespace
