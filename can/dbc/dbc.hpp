// A DBC file read at run time: what `lptn replay/convert/vcan-bench --bus` need of a converter's
// DBC (messages, their signals' layout, scaling and multiplexing, the cycle time). The build reads
// DBC files with can/codecs/dbc_codegen.py instead and generates codecs; this reader follows the same
// rules (tokens, sections, what stops and what is read past), so a file means the same on both
// routes, and its signal arithmetic is the generated codecs' bit for bit (tests/dbc holds them
// equal on our DBC files and the real-world corpus).
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "hostio/bad_input.hpp"

namespace lptn::dbc {

// "FILE:LINE: reason" for what would make a frame undecodable.
class Error : public BadInput {
 public:
  using BadInput::BadInput;
};

struct Signal {
  enum class Mux { none, multiplexor, multiplexed };

  std::string name, unit;
  int start = 0, length = 0;  // DBC start bit (Motorola: the MSB, sawtooth numbering), bits
  bool big_endian = false, is_signed = false;
  double factor = 1, offset = 0, minimum = 0, maximum = 0;
  Mux mux = Mux::none;
  std::vector<std::pair<std::int64_t, std::int64_t>> mux_ranges;  // multiplexed: values that carry it
  std::int64_t mux_value = 0;  // multiplexed: the first value that carries it (what encoding writes)
  bool is_float = false;       // SIG_VALTYPE_ 1/2: refused, as the generator does
  int line = 0;
};

struct Message {
  std::string name, sender;
  std::uint32_t id = 0;  // without the extended flag
  bool extended = false;
  int length = 0;        // bytes (DLC as written, up to 64)
  std::vector<Signal> signals;
  int line = 0;
  std::uint32_t cycle_ms = 0;  // GenMsgCycleTime, else its BA_DEF_DEF_ default, else 0

  const Signal* find(std::string_view signal) const;
  const Signal* multiplexor() const;
};

struct Database {
  std::string path;
  std::vector<Message> messages;  // frames only: no pseudo message, no id a CAN frame cannot have
  std::vector<std::string> warnings;  // "FILE:LINE: warning: reason", what the file reads past

  const Message* find(std::string_view name) const;
  const Message* find(std::uint32_t id, bool extended) const;
};

// Latin-1 or UTF-8, LF or CRLF. Throws Error.
Database read(const std::filesystem::path& file);
Database parse(std::string_view text, std::string path);

// The signal's raw bits from a frame of `len` bytes (sign-extended if signed); false if the frame
// is too short to hold them.
bool extract_raw(const Signal& s, const std::uint8_t* data, int len, std::int64_t& raw);
// Writes the raw value's low `length` bits into the frame (bits of other signals untouched).
void insert_raw(const Signal& s, std::int64_t raw, std::uint8_t* data, int len);
// raw * factor + offset, as the generated NAME_decode().
double to_physical(const Signal& s, std::int64_t raw);
// round((physical - offset) / factor), halves away from zero, saturated to what the bits hold,
// NaN -> 0: the generated NAME_encode().
std::int64_t to_raw(const Signal& s, double physical);
// Whether the frame carries a signal: always, unless it is multiplexed and the multiplexor's value
// is not one of its values.
bool present(const Message& m, const Signal& s, const std::uint8_t* data, int len);

}  // namespace lptn::dbc
