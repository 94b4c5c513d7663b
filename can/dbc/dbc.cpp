// A DBC file's Database (read, then checked by check.cpp) and the signal arithmetic of its generated
// codecs.
#include "can/dbc/dbc.hpp"

#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

#include "can/dbc/internal/check.hpp"
#include "can/dbc/internal/parser.hpp"
#include "hostio/utf8.hpp"

namespace lptn::dbc {
namespace {

namespace fs = std::filesystem;

std::pair<long long, long long> raw_limits(const Signal& s) {
  if (s.length >= 64)
    return s.is_signed ? std::pair{std::numeric_limits<long long>::min(), std::numeric_limits<long long>::max()}
                       : std::pair{0LL, std::numeric_limits<long long>::max()};
  if (s.is_signed) return {-(1LL << (s.length - 1)), (1LL << (s.length - 1)) - 1};
  return {0, (1LL << s.length) - 1};
}

}  // namespace

const Signal* Message::find(std::string_view signal) const {
  for (const Signal& s : signals)
    if (s.name == signal) return &s;
  return nullptr;
}

const Signal* Message::multiplexor() const {
  for (const Signal& s : signals)
    if (s.mux == Signal::Mux::multiplexor) return &s;
  return nullptr;
}

const Message* Database::find(std::string_view message) const {
  for (const Message& m : messages)
    if (m.name == message) return &m;
  return nullptr;
}

const Message* Database::find(std::uint32_t id, bool extended) const {
  for (const Message& m : messages)
    if (m.id == id && m.extended == extended) return &m;
  return nullptr;
}

Database parse(std::string_view text, std::string path, std::string_view node) {
  try {
    internal::Document doc = internal::parse_document(internal::tokenize(text));
    return internal::check(doc, path, node);
  } catch (const internal::ParseError& e) {
    throw Error(path + ":" + std::to_string(e.line) + ": " + e.reason);
  }
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ":0: cannot read the file");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return hostio::as_utf8(bytes.str());  // UTF-8, or Latin-1 (cp1252) as UTF-8
}

Database read(const fs::path& file, std::string_view node) { return parse(read_text(file), file.string(), node); }

bool extract_raw(const Signal& s, const std::uint8_t* data, int len, std::int64_t& raw) {
  std::uint64_t bits = 0;
  const std::vector<int> where = internal::frame_bits(s);
  for (int i = 0; i < s.length; ++i) {
    const int bit = where[static_cast<std::size_t>(i)];
    if (bit < 0 || bit / 8 >= len) return false;
    if ((data[bit / 8] >> (bit % 8)) & 1u) bits |= std::uint64_t{1} << i;
  }
  if (s.is_signed && s.length < 64 && (bits >> (s.length - 1)) & 1u) bits |= ~std::uint64_t{0} << s.length;
  raw = static_cast<std::int64_t>(bits);
  return true;
}

void insert_raw(const Signal& s, std::int64_t raw, std::uint8_t* data, int len) {
  const auto bits = static_cast<std::uint64_t>(raw);
  const std::vector<int> where = internal::frame_bits(s);
  for (int i = 0; i < s.length; ++i) {
    const int bit = where[static_cast<std::size_t>(i)];
    if (bit < 0 || bit / 8 >= len) continue;
    const auto mask = static_cast<std::uint8_t>(1u << (bit % 8));
    if ((bits >> i) & 1u)
      data[bit / 8] = static_cast<std::uint8_t>(data[bit / 8] | mask);
    else
      data[bit / 8] = static_cast<std::uint8_t>(data[bit / 8] & ~mask);
  }
}

double to_physical(const Signal& s, std::int64_t raw) {
  // An unsigned 64-bit raw value is its bits taken as unsigned, as the generated code's uint64_t.
  const double r = (!s.is_signed && s.length == 64) ? static_cast<double>(static_cast<std::uint64_t>(raw)) : static_cast<double>(raw);
  return r * s.factor + s.offset;  // x * 1.0 and x + 0.0 are x: the generated code's terms
}

std::int64_t to_raw(const Signal& s, double physical) {
  const double x = (physical - s.offset) / s.factor;
  const auto [low, high] = raw_limits(s);
  if (s.is_signed) {
    if (x > static_cast<double>(low) && x < static_cast<double>(high)) {
      const auto whole = static_cast<std::int64_t>(x);
      const double rest = x - static_cast<double>(whole);
      return rest >= 0.5 ? whole + 1 : rest <= -0.5 ? whole - 1 : whole;
    }
    if (x >= static_cast<double>(high)) return high;
    if (x <= static_cast<double>(low)) return low;
    return 0;
  }
  const std::uint64_t uhigh = s.length >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << s.length) - 1;
  if (x > 0.0 && x < static_cast<double>(uhigh)) {
    const auto whole = static_cast<std::uint64_t>(x);
    return static_cast<std::int64_t>(x - static_cast<double>(whole) >= 0.5 ? whole + 1 : whole);
  }
  if (x >= static_cast<double>(uhigh)) return static_cast<std::int64_t>(uhigh);
  return 0;
}

bool present(const Message& m, const Signal& s, const std::uint8_t* data, int len) {
  if (s.mux != Signal::Mux::multiplexed) return true;
  const Signal* mux = m.multiplexor();
  std::int64_t value = 0;
  if (!mux || !extract_raw(*mux, data, len, value)) return false;
  for (const auto& [low, high] : s.mux_ranges)
    if (low <= value && value <= high) return true;
  return false;
}

}  // namespace lptn::dbc
