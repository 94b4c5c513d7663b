// A DBC file, read once for both routes: at run time for `lptn replay/convert/vcan-bench --bus`
// (messages, their signals' layout, scaling and multiplexing, the cycle time), and at build time by
// lptn-can-codegen (can/codegen), which writes the codecs from the same Database (comments, value
// descriptions, the texts of the numbers as written). A file means the same on both routes because
// it is the same reading; the signal arithmetic below is the generated codecs' bit for bit
// (tests/dbc holds it to a model of the frame, as tests/codecs' corpus reference holds the codecs).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "hostio/bad_input.hpp"

namespace lptn::dbc {

// "FILE:LINE: reason" for what would make a frame undecodable.
class Error : public hostio::BadInput {
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

  // What the generated codecs say beside the arithmetic.
  std::string factor_text, offset_text, minimum_text, maximum_text;  // the numbers as written
  std::vector<std::string> receivers;
  std::string comment;                                             // CM_ SG_, "" if none
  std::vector<std::pair<std::int64_t, std::string>> values;        // VAL_ that fit the bits; empty if none
  // [min|max] as raw values, computed exactly: nullopt where the range is [0|0] or cannot be right
  // (range_ignored). The ends are ceil and floor of the exact bounds, clamped to +-2^64.
  bool range_ignored = false;
  struct RawRange {
    long double low, high;  // whole numbers within +-2^64: exact in a long double's 64-bit mantissa
  };
  std::optional<RawRange> raw_range;
};

struct Message {
  std::string name, sender;
  std::uint32_t id = 0;  // without the extended flag
  bool extended = false;
  int length = 0;        // bytes (DLC as written, up to 64)
  std::vector<Signal> signals;
  int line = 0;
  std::uint32_t cycle_ms = 0;  // GenMsgCycleTime, else its BA_DEF_DEF_ default, else 0
  std::string comment;               // CM_ BO_, "" if none
  std::vector<std::string> transmitters;  // BO_TX_BU_

  const Signal* find(std::string_view signal) const;
  const Signal* multiplexor() const;
};

struct Warning {
  int line;
  std::string reason;
};

struct Database {
  std::string path;
  std::vector<Message> messages;  // frames only: no pseudo message, no id a CAN frame cannot have
  std::vector<Warning> warnings;  // what the reading read past, in the order of their lines
  std::string comment;                // CM_ of the network
  std::map<std::string, std::string> node_comments;  // CM_ BU_

  const Message* find(std::string_view name) const;
  const Message* find(std::uint32_t id, bool extended) const;
};

// The node "none" of DBC tools; as `node` below: read for no node in particular (a logger's view).
inline constexpr std::string_view kNoNode = "Vector__XXX";

// Latin-1 or UTF-8, LF or CRLF. Throws Error. `node` is the one the reading is for: a signal outside
// its frame is refused if the node sends or receives it, else left out with a warning; a node not in
// BU_ is refused.
Database read(const std::filesystem::path& file, std::string_view node = kNoNode);
Database parse(std::string_view text, std::string path, std::string_view node = kNoNode);
// The file's text as both routes read it: UTF-8 if it is, else Latin-1. Throws Error.
std::string read_text(const std::filesystem::path& file);

// The sign of (the number as the DBC writes it, e.g. "1.0000000000000000001") - value, computed
// exactly: where the generated code leaves out `* factor` or `+ offset`, a double's rounding must
// not decide it.
int compare_exact(const std::string& number, long long value);

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
