// Every signal of every message of every DBC file the tree has (ours, the generator's good and
// warning cases, the foreign converter's, the real-world corpus), on 20 pseudo-random payloads per
// message: the reader's raw value (extract_raw, which the generated unpack() mirrors) against the
// frame read as one big number, Intel signals from its least significant end and Motorola ones from
// its most significant, without the DBC's sawtooth bit numbering; and to_physical() as the generated
// NAME_decode() computes it.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "can/dbc/dbc.hpp"

namespace lptn::dbc {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> dbc_files() {
  const fs::path root = LPTN_SOURCE_DIR;
  std::vector<fs::path> files = {root / "can/codecs/lptn.dbc", root / "tests/codecs/codec_test.dbc"};
  for (const char* dir : {"tests/codecs/good", "tests/codecs/warn", "tests/codecs/corpus", "tests/bus/foreign"})
    for (const auto& entry : fs::directory_iterator(root / dir))
      if (entry.path().extension() == ".dbc") files.push_back(entry.path());
  return files;
}

std::uint64_t xorshift(std::uint64_t& state) {
  state ^= state << 13;
  state ^= state >> 7;
  state ^= state << 17;
  return state;
}

// The model: bit q of the frame counted from the first byte's least (Intel) or most (Motorola)
// significant bit.
int intel_bit(const std::uint8_t* data, int q) { return (data[q / 8] >> (q % 8)) & 1; }
int motorola_bit(const std::uint8_t* data, int q) { return (data[q / 8] >> (7 - q % 8)) & 1; }

std::int64_t model_raw(const Signal& s, const std::uint8_t* data) {
  std::uint64_t bits = 0;
  if (s.big_endian) {
    const int msb = 8 * (s.start / 8) + 7 - s.start % 8;  // the start bit in Motorola order
    for (int k = 0; k < s.length; ++k) bits = (bits << 1) | static_cast<std::uint64_t>(motorola_bit(data, msb + k));
  } else {
    for (int k = s.length - 1; k >= 0; --k) bits = (bits << 1) | static_cast<std::uint64_t>(intel_bit(data, s.start + k));
  }
  if (s.is_signed && s.length < 64 && (bits >> (s.length - 1)) & 1u) bits |= ~std::uint64_t{0} << s.length;
  return static_cast<std::int64_t>(bits);
}

TEST(DbcReader, DecodesEverySignalAsTheFrameReadAsOneNumber) {
  std::uint64_t state = 0x9E3779B97F4A7C15u;
  int files = 0, payloads = 0;
  for (const fs::path& file : dbc_files()) {
    SCOPED_TRACE(file.string());
    const Database db = read(file);
    ++files;
    for (const Message& m : db.messages) {
      for (int n = 0; n < 20; ++n) {
        std::uint8_t data[64] = {};
        for (int i = 0; i < m.length; ++i) data[i] = static_cast<std::uint8_t>(xorshift(state));
        ++payloads;
        for (const Signal& s : m.signals) {
          std::int64_t raw = 0;
          ASSERT_TRUE(extract_raw(s, data, m.length, raw)) << m.name << "." << s.name;
          ASSERT_EQ(raw, model_raw(s, data)) << m.name << "." << s.name;
          const double r = (!s.is_signed && s.length == 64) ? static_cast<double>(static_cast<std::uint64_t>(raw))
                                                            : static_cast<double>(raw);
          ASSERT_EQ(to_physical(s, raw), r * s.factor + s.offset) << m.name << "." << s.name;
        }
      }
    }
  }
  EXPECT_GT(files, 80);
  EXPECT_GT(payloads, 1000);
}

}  // namespace
}  // namespace lptn::dbc
