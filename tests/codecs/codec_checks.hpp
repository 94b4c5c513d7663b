// Checks every generated message must pass, written against an independent model of where DBC
// puts a signal's bits. The generated code works byte by byte; the model below works on the whole
// frame as one 64-bit word, so the two can only agree if both are right.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <random>
#include <type_traits>

namespace lptn::can::checks {

// One signal as the generated code exposes it: the raw member and the three static functions.
template <typename Message, typename Raw>
struct SignalAccess {
  using raw_type = Raw;
  Raw Message::*member;
  double (*decode)(Raw) noexcept;
  Raw (*encode)(double) noexcept;
  bool (*is_in_range)(Raw) noexcept;
};

// LPTN_CAN_SIGNAL(TcElectrical, motor_speed): the SignalAccess of one signal.
#define LPTN_CAN_SIGNAL(Message, name)                                                   \
  ::lptn::can::checks::SignalAccess<Message, decltype(Message::name)> {                  \
    &Message::name, &Message::name##_decode, &Message::name##_encode,                    \
        &Message::name##_is_in_range                                                     \
  }

using Frame = std::array<std::uint8_t, 8>;

inline std::uint64_t low_bits(unsigned length) {
  return length == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << length) - 1;
}

// --- The reference model -----------------------------------------------------------------------
// Intel (@1): the frame read as a little-endian word; the signal's LSB is word bit `start`.
// Motorola (@0): the frame read as a big-endian word. DBC's start bit is the signal's MSB, given in
// the sawtooth numbering (bit 7 of byte 0 is 7, its bit 0 is 0, bit 7 of byte 1 is 15). Counted
// instead from the frame's first bit on the wire (byte 0's MSB = 0), the MSB is at
// 8 * (start / 8) + 7 - start % 8, and the signal's bits are the `length` consecutive ones from
// there: in the big-endian word its LSB sits at bit 64 - msb - length.

inline unsigned word_shift(unsigned start, unsigned length, bool big_endian) {
  if (!big_endian) {
    return start;
  }
  const unsigned msb_on_wire = 8 * (start / 8) + 7 - start % 8;
  return 64 - msb_on_wire - length;
}

inline std::uint64_t to_word(const Frame& frame, bool big_endian) {
  std::uint64_t word = 0;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    word |= std::uint64_t{frame[i]} << (big_endian ? 56 - 8 * i : 8 * i);
  }
  return word;
}

inline Frame from_word(std::uint64_t word, bool big_endian) {
  Frame frame{};
  for (std::size_t i = 0; i < frame.size(); ++i) {
    frame[i] = static_cast<std::uint8_t>(word >> (big_endian ? 56 - 8 * i : 8 * i));
  }
  return frame;
}

template <typename Info>
std::uint64_t reference_get(const Frame& frame, const Info& info) {
  const std::uint64_t word = to_word(frame, info.big_endian);
  return (word >> word_shift(info.start, info.length, info.big_endian)) & low_bits(info.length);
}

template <typename Info>
void reference_set(Frame& frame, const Info& info, std::uint64_t bits) {
  const unsigned shift = word_shift(info.start, info.length, info.big_endian);
  const std::uint64_t word = to_word(frame, info.big_endian) | (bits & low_bits(info.length)) << shift;
  frame = from_word(word, info.big_endian);
}

// --- Raw values --------------------------------------------------------------------------------

// The signal's bits of a raw value (two's complement for signed ones).
template <typename Raw>
std::uint64_t to_bits(Raw raw, unsigned length) {
  return static_cast<std::uint64_t>(raw) & low_bits(length);
}

// The raw value `length` bits stand for: sign-extended when the signal is signed.
template <typename Raw, typename Info>
Raw from_bits(std::uint64_t bits, const Info& info) {
  bits &= low_bits(info.length);
  if (info.is_signed && info.length < 64 && (bits >> (info.length - 1)) != 0) {
    bits |= ~low_bits(info.length);
  }
  return static_cast<Raw>(bits);  // modulo 2^N: the two's complement value
}

template <typename Raw, typename Info>
Raw raw_max(const Info& info) {
  return from_bits<Raw>(info.is_signed ? low_bits(info.length - 1) : low_bits(info.length), info);
}

template <typename Raw, typename Info>
Raw raw_min(const Info& info) {
  return info.is_signed ? from_bits<Raw>(std::uint64_t{1} << (info.length - 1), info) : Raw{0};
}

// Calls f(kSignals[i], signals[i]) for every signal, in DBC order.
template <typename Message, typename F, typename... Raw>
void for_each_signal(F f, const SignalAccess<Message, Raw>&... signals) {
  std::size_t index = 0;
  (f(Message::kSignals[index++], signals), ...);
}

inline Frame random_frame(std::mt19937_64& random) {
  Frame frame{};
  for (auto& byte : frame) {
    byte = static_cast<std::uint8_t>(random());
  }
  return frame;
}

inline bool same_bytes(const Frame& a, const Frame& b, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) {
    if (a[i] != b[i]) {
      return false;
    }
  }
  return true;
}

// --- The checks --------------------------------------------------------------------------------

// pack() puts each raw value's low `length` bits where the model says and nothing else (the raws
// carry garbage above their length); unpack() reads back what the model reads.
template <typename Message, typename... Raw>
void check_layout(std::mt19937_64& random, const SignalAccess<Message, Raw>&... signals) {
  for (int trial = 0; trial < 2000; ++trial) {
    Message message;
    Frame expected{};
    for_each_signal<Message>(
        [&](const auto& info, const auto& signal) {
          using R = typename std::remove_cvref_t<decltype(signal)>::raw_type;
          message.*signal.member = static_cast<R>(random());
          reference_set(expected, info, to_bits(message.*signal.member, info.length));
        },
        signals...);
    Frame packed;
    packed.fill(0xA5);
    ASSERT_TRUE(message.pack(packed.data(), Message::kLength));
    ASSERT_TRUE(same_bytes(packed, expected, Message::kLength)) << "trial " << trial;
    for (std::size_t i = Message::kLength; i < packed.size(); ++i) {
      ASSERT_EQ(packed[i], 0xA5) << "pack wrote past kLength";
    }

    const Frame frame = random_frame(random);
    Message decoded;
    ASSERT_TRUE(decoded.unpack(frame.data(), Message::kLength));
    for_each_signal<Message>(
        [&](const auto& info, const auto& signal) {
          using R = typename std::remove_cvref_t<decltype(signal)>::raw_type;
          Frame visible{};  // the model sees only the kLength bytes unpack() may read
          std::copy_n(frame.begin(), Message::kLength, visible.begin());
          ASSERT_EQ(decoded.*signal.member, from_bits<R>(reference_get(visible, info), info))
              << info.name << ", trial " << trial;
        },
        signals...);
  }
}

// Any raw values the signals' bits hold survive pack() then unpack().
template <typename Message, typename... Raw>
void check_round_trip(std::mt19937_64& random, const SignalAccess<Message, Raw>&... signals) {
  for (int trial = 0; trial < 1000; ++trial) {
    Message message;
    for_each_signal<Message>(
        [&](const auto& info, const auto& signal) {
          using R = typename std::remove_cvref_t<decltype(signal)>::raw_type;
          message.*signal.member = from_bits<R>(random(), info);
        },
        signals...);
    Frame frame{};
    ASSERT_TRUE(message.pack(frame.data(), Message::kLength));
    Message decoded;
    ASSERT_TRUE(decoded.unpack(frame.data(), Message::kLength));
    for_each_signal<Message>(
        [&](const auto& info, const auto& signal) {
          ASSERT_EQ(decoded.*signal.member, message.*signal.member) << info.name << ", trial " << trial;
        },
        signals...);
  }
}

// Too short a buffer: unpack() changes nothing, pack() writes nothing.
template <typename Message, typename... Raw>
void check_short_buffers(std::mt19937_64& random, const SignalAccess<Message, Raw>&... signals) {
  Message original;
  for_each_signal<Message>(
      [&](const auto& info, const auto& signal) {
        using R = typename std::remove_cvref_t<decltype(signal)>::raw_type;
        original.*signal.member = from_bits<R>(random(), info);
      },
      signals...);
  const Frame frame = random_frame(random);
  for (std::size_t size = 0; size < Message::kLength; ++size) {
    Message message = original;
    EXPECT_FALSE(message.unpack(frame.data(), size)) << "size " << size;
    for_each_signal<Message>(
        [&](const auto& info, const auto& signal) {
          EXPECT_EQ(message.*signal.member, original.*signal.member) << info.name << ", size " << size;
        },
        signals...);
    Frame buffer;
    buffer.fill(0xAA);
    EXPECT_FALSE(original.pack(buffer.data(), size)) << "size " << size;
    for (const std::uint8_t byte : buffer) {
      EXPECT_EQ(byte, 0xAA) << "pack wrote into a buffer of " << size << " bytes";
    }
  }
}

// encode, decode and is_in_range against the signal's DBC definition (kSignals).
template <typename Info, typename Message, typename Raw>
void check_scaling(std::mt19937_64& random, const Info& info, const SignalAccess<Message, Raw>& signal) {
  SCOPED_TRACE(info.name);
  const double factor = info.factor;
  const double lsb = std::abs(factor);
  const Raw lowest = raw_min<Raw>(info);
  const Raw highest = raw_max<Raw>(info);

  EXPECT_EQ(signal.encode(std::numeric_limits<double>::quiet_NaN()), Raw{0});
  // Saturation: far outside, at infinity, and one step past the raw range (where doubles resolve it).
  const double far = 1e300;
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(signal.encode(factor > 0 ? far : -far), highest);
  EXPECT_EQ(signal.encode(factor > 0 ? -far : far), lowest);
  EXPECT_EQ(signal.encode(factor > 0 ? inf : -inf), highest);
  EXPECT_EQ(signal.encode(factor > 0 ? -inf : inf), lowest);
  if (info.length <= 52) {
    EXPECT_EQ(signal.encode(signal.decode(highest) + factor), highest);
    EXPECT_EQ(signal.encode(signal.decode(lowest) - factor), lowest);
    EXPECT_EQ(signal.encode(signal.decode(highest)), highest);
    EXPECT_EQ(signal.encode(signal.decode(lowest)), lowest);
  }

  // decode(encode(x)) within half a step of x inside the range ([0|0]: the raw range, kept to
  // values doubles hold exactly).
  const bool unranged = info.min == 0.0 && info.max == 0.0;
  const double limit = std::ldexp(1.0, 52);
  const double low = unranged ? signal.decode(static_cast<Raw>(std::max<double>(static_cast<double>(lowest), -limit)))
                              : info.min;
  const double high = unranged ? signal.decode(static_cast<Raw>(std::min<double>(static_cast<double>(highest), limit)))
                               : info.max;
  std::uniform_real_distribution<double> physical(std::min(low, high), std::max(low, high));
  for (int trial = 0; trial < 1000; ++trial) {
    const double x = physical(random);
    EXPECT_NEAR(signal.decode(signal.encode(x)), x, lsb / 2 * (1 + 1e-9) + std::abs(x) * 1e-15) << "x = " << x;
  }

  if (unranged) {
    EXPECT_TRUE(signal.is_in_range(lowest));
    EXPECT_TRUE(signal.is_in_range(highest));
  } else {
    EXPECT_TRUE(signal.is_in_range(signal.encode(info.min)));
    EXPECT_TRUE(signal.is_in_range(signal.encode(info.max)));
    // One step beyond each end, unless the raw bits end there too.
    const Raw below = signal.encode(info.min - lsb);
    if (signal.decode(below) < info.min - lsb / 2) {
      EXPECT_FALSE(signal.is_in_range(below));
    }
    const Raw above = signal.encode(info.max + lsb);
    if (signal.decode(above) > info.max + lsb / 2) {
      EXPECT_FALSE(signal.is_in_range(above));
    }
  }
  // Everywhere: in range exactly when the physical value is (a millionth of a step for rounding).
  for (int trial = 0; trial < 1000; ++trial) {
    const Raw raw = from_bits<Raw>(random(), info);
    const double value = signal.decode(raw);
    const bool inside = unranged || (value >= info.min - lsb * 1e-6 && value <= info.max + lsb * 1e-6);
    EXPECT_EQ(signal.is_in_range(raw), inside) << "raw " << +raw << " = " << value;
  }
}

// Each raw member is the smallest std::[u]intN_t that holds the signal, signed as the signal is.
template <typename Message, typename... Raw>
void check_raw_types(const SignalAccess<Message, Raw>&... signals) {
  for_each_signal<Message>(
      [](const auto& info, const auto& signal) {
        using R = typename std::remove_cvref_t<decltype(signal)>::raw_type;
        constexpr unsigned width = sizeof(R) * 8;
        EXPECT_TRUE(info.length <= width && (width == 8 || info.length > width / 2)) << info.name;
        EXPECT_EQ(std::is_signed_v<R>, info.is_signed) << info.name;
      },
      signals...);
}

// All of the above for one message; list its signals in DBC order.
template <typename Message, typename... Raw>
void check_message(const SignalAccess<Message, Raw>&... signals) {
  static_assert(sizeof...(Raw) == Message::kNumSignals, "list every signal of the message");
  std::mt19937_64 random(Message::kId);  // a fixed seed per message: failures reproduce
  check_raw_types(signals...);
  check_layout(random, signals...);
  check_round_trip(random, signals...);
  check_short_buffers(random, signals...);
  for_each_signal<Message>([&](const auto& info, const auto& signal) { check_scaling(random, info, signal); },
                           signals...);
}

}  // namespace lptn::can::checks
