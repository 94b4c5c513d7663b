// A DBC file's frames, checked as can/codecs/dbc_codegen.py's Checker checks them (without a --node:
// every signal must fit its frame), and the signal arithmetic of its generated codecs.
#include "can/dbc/dbc.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "hostio/utf8.hpp"
#include "can/dbc/internal/parser.hpp"

namespace lptn::dbc {
namespace {

namespace fs = std::filesystem;
using internal::Document;
using internal::Number;
using internal::ParseError;
using internal::RawMessage;
using internal::RawSignal;
using internal::Statement;

constexpr std::uint64_t kExtendedFlag = 0x80000000u;
constexpr std::uint64_t kIndependentSignalsId = 0xC0000000u;  // Vector's pseudo message: not a frame
constexpr int kFdLengths[] = {12, 16, 20, 24, 32, 48, 64};
const std::string kNoNode = "Vector__XXX";

std::string hex(std::uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "0x%llX", static_cast<unsigned long long>(v));
  return buf;
}

// Frame bit (8 * byte + bit in byte) of each value bit, least significant first.
std::vector<int> frame_bits(const Signal& s) {
  std::vector<int> bits(static_cast<std::size_t>(s.length));
  if (!s.big_endian) {
    for (int i = 0; i < s.length; ++i) bits[static_cast<std::size_t>(i)] = s.start + i;
    return bits;
  }
  // Motorola: the start bit is the MSB; after bit 0 of a byte the signal goes on at bit 7 of the next.
  int position = s.start;
  for (int i = s.length - 1; i >= 0; --i) {
    bits[static_cast<std::size_t>(i)] = position;
    position = position % 8 == 0 ? position + 15 : position - 1;
  }
  return bits;
}

std::pair<long long, long long> raw_limits(const Signal& s) {
  if (s.length >= 64)
    return s.is_signed ? std::pair{std::numeric_limits<long long>::min(), std::numeric_limits<long long>::max()}
                       : std::pair{0LL, std::numeric_limits<long long>::max()};
  if (s.is_signed) return {-(1LL << (s.length - 1)), (1LL << (s.length - 1)) - 1};
  return {0, (1LL << s.length) - 1};
}

std::string format_value(const Number& n) {
  if (n.whole) return std::to_string(n.integer);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", n.value);
  return buf;
}

class Checker {
 public:
  Checker(Document& doc, std::string path) : doc_(doc), path_(std::move(path)) {}

  Database run() {
    check_nodes();
    check_messages();
    for (const Statement& st : doc_.statements) resolve(st);
    Database db;
    db.path = path_;
    for (std::size_t i = 0; i < doc_.messages.size(); ++i) {
      const RawMessage& raw = doc_.messages[i];
      if (raw.dbc_id == kIndependentSignalsId || left_out_.count(i)) continue;
      Message m;
      m.name = raw.name;
      m.sender = raw.sender;
      m.id = static_cast<std::uint32_t>(raw.dbc_id & ~kExtendedFlag);
      m.extended = (raw.dbc_id & kExtendedFlag) || m.id > 0x7FF;
      m.length = static_cast<int>(raw.dlc);
      m.line = raw.line;
      m.cycle_ms = cycle_.count(i) ? cycle_[i] : default_cycle_;
      for (const RawSignal& s : raw.signals) m.signals.push_back(s.signal);
      db.messages.push_back(std::move(m));
    }
    std::stable_sort(warnings_.begin(), warnings_.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [line, reason] : warnings_) db.warnings.push_back(path_ + ":" + std::to_string(line) + ": warning: " + reason);
    return db;
  }

 private:
  [[noreturn]] static void fail(int line, const std::string& reason) { throw ParseError{line, reason}; }
  void warn(int line, std::string reason) { warnings_.emplace_back(line, std::move(reason)); }

  void check_nodes() {
    for (auto& w : doc_.warnings) warnings_.push_back(w);
    if (!doc_.nodes_line) warn(1, "the file has no BU_ section; senders and receivers are not checked");
    for (const auto& [name, line] : doc_.nodes) {
      if (auto it = nodes_.find(name); it != nodes_.end()) {
        warn(line, "node " + name + " is listed twice in BU_ (first on line " + std::to_string(it->second) + ")");
        continue;
      }
      nodes_.emplace(name, line);
    }
  }
  void check_node(const std::string& name, int line, const std::string& role) {
    if (name == kNoNode || nodes_.count(name) || !doc_.nodes_line) return;
    if (unknown_nodes_.insert(name).second) warn(line, role + " '" + name + "' is not a node in BU_");
  }

  void check_messages() {
    std::map<std::string, int> by_name;
    std::map<std::pair<bool, std::uint64_t>, const RawMessage*> by_frame;
    for (std::size_t i = 0; i < doc_.messages.size(); ++i) {
      RawMessage& m = doc_.messages[i];
      const std::uint64_t can_id = m.dbc_id & ~kExtendedFlag;
      if (auto it = by_id_.find(m.dbc_id); it != by_id_.end()) {
        const RawMessage& first = doc_.messages[it->second];
        fail(m.line, "message id " + std::to_string(m.dbc_id) + " (" + hex(can_id) + ") is already used by " + first.name +
                         " on line " + std::to_string(first.line));
      }
      by_id_.emplace(m.dbc_id, i);
      if (m.dbc_id == kIndependentSignalsId) continue;
      if (auto it = by_name.find(m.name); it != by_name.end())
        fail(m.line, "message name " + m.name + " is already used on line " + std::to_string(it->second));
      by_name.emplace(m.name, m.line);
      const std::string where = "message " + m.name;
      bool extended = m.dbc_id & kExtendedFlag;
      if (extended && can_id > 0x1FFFFFFF) {
        left_out_.insert(i);
        warn(m.line, where + ": extended id " + hex(can_id) + " does not fit in 29 bits; no CAN frame has it, so the message is left out");
      } else if (!extended && can_id > 0x1FFFFFFF) {
        left_out_.insert(i);
        warn(m.line, where + ": id " + std::to_string(m.dbc_id) + " (" + hex(m.dbc_id) +
                         ") fits neither 11 nor 29 bits and has no extended flag (0x80000000); no CAN frame has it, so the message is left out");
      } else if (can_id > 0x7FF) {
        extended = true;
        warn(m.line, where + ": id " + hex(can_id) +
                         " does not fit in 11 bits and has no extended flag (0x80000000); taken as a 29-bit extended id");
      }
      if (left_out_.count(i)) continue;
      const auto key = std::pair{extended, can_id};
      if (auto it = by_frame.find(key); it != by_frame.end())
        fail(m.line, where + ": " + (extended ? "extended" : "standard") + " id " + hex(can_id) + " is already used by " +
                         it->second->name + " on line " + std::to_string(it->second->line));
      by_frame.emplace(key, &m);
      check_message(m);
    }
  }

  void check_message(RawMessage& m) {
    const std::string where = "message " + m.name;
    if (m.dlc > 64) fail(m.line, where + ": length " + std::to_string(m.dlc) + " is more than 64 bytes, CAN FD's longest frame");
    if (m.dlc > 8 && std::find(std::begin(kFdLengths), std::end(kFdLengths), m.dlc) == std::end(kFdLengths))
      warn(m.line, where + ": length " + std::to_string(m.dlc) + " is not a CAN FD frame length");
    check_node(m.sender, m.line, where + ": sender");
    if (m.signals.empty()) warn(m.line, where + " has no signals");
    std::map<std::string, int> names;
    std::vector<RawSignal> kept;
    for (RawSignal& r : m.signals) {
      const Signal& s = r.signal;
      if (auto it = names.find(s.name); it != names.end())
        fail(s.line, "signal " + s.name + " appears twice in message " + m.name + " (first on line " + std::to_string(it->second) + ")");
      names.emplace(s.name, s.line);
      if (check_signal(m, r))
        kept.push_back(std::move(r));
      else
        left_out_signals_.insert({m.line, s.name});
    }
    m.signals = std::move(kept);
    const Signal* multiplexor = nullptr;
    for (const RawSignal& r : m.signals) {
      if (r.signal.mux != Signal::Mux::multiplexor) continue;
      if (multiplexor)
        fail(r.signal.line, "signal " + r.signal.name + ": message " + m.name + " already has a multiplexor (" + multiplexor->name +
                                ", line " + std::to_string(multiplexor->line) + "); extended multiplexing is not supported");
      multiplexor = &r.signal;
    }
    for (const RawSignal& r : m.signals)
      if (r.signal.mux == Signal::Mux::multiplexed && !multiplexor)
        fail(r.signal.line, "signal " + r.signal.name + " is multiplexed (m" + std::to_string(r.signal.mux_value) + ") but message " +
                                m.name + " has no multiplexor (M)");
  }

  // False: the signal lies outside its frame and is left out, as the codecs generated for the whole
  // bus (--node Vector__XXX) leave it out.
  bool check_signal(const RawMessage& m, const RawSignal& r) {
    const Signal& s = r.signal;
    const std::string where = "signal " + s.name;
    if (s.length < 1 || s.length > 64) fail(s.line, where + ": length " + std::to_string(s.length) + " is not in 1..64");
    if (s.factor == 0) fail(s.line, where + ": factor 0 (every raw value would decode to the offset)");
    for (const std::string& receiver : r.receivers) check_node(receiver, s.line, where + ": receiver");
    const std::vector<int> bits = frame_bits(s);
    if (*std::max_element(bits.begin(), bits.end()) >= 8 * m.dlc || *std::min_element(bits.begin(), bits.end()) < 0)
    {
      warn(s.line, where + " (" + (s.big_endian ? "big-endian" : "little-endian") + ", start bit " + std::to_string(s.start) + ", " +
                       std::to_string(s.length) + " bits) overflows its " + std::to_string(m.dlc) + "-byte frame; " + kNoNode +
                       " neither sends nor receives it, so it is left out");
      return false;
    }
    return true;
  }

  // -- statements that name other objects
  std::pair<RawMessage*, std::size_t> message(std::uint64_t id, int line, const std::string& statement) {
    auto it = by_id_.find(id);
    if (it == by_id_.end()) {
      warn(line, "no message has id " + std::to_string(id) + "; the " + statement + " is ignored");
      return {nullptr, 0};
    }
    return {&doc_.messages[it->second], it->second};
  }
  RawSignal* signal(RawMessage* m, const std::string& name, int line, const std::string& statement) {
    if (!m) return nullptr;
    for (RawSignal& r : m->signals)
      if (r.signal.name == name) return &r;
    if (left_out_signals_.count({m->line, name})) return nullptr;  // read past, as the generator does
    warn(line, "message " + m->name + " has no signal " + name + "; the " + statement + " is ignored");
    return nullptr;
  }
  bool generated(std::size_t index) const {
    return doc_.messages[index].dbc_id != kIndependentSignalsId && !left_out_.count(index);
  }

  const internal::AttributeDef& definition(const std::string& name, int line) {
    auto it = doc_.attribute_defs.find(name);
    if (it == doc_.attribute_defs.end()) fail(line, "attribute \"" + name + "\" has no BA_DEF_");
    return it->second;
  }
  static void check_attribute_value(const std::string& name, const internal::AttributeDef& d, const internal::Value& v, int line) {
    const Number* n = std::get_if<Number>(&v);
    if (d.type == "INT" || d.type == "HEX" || d.type == "FLOAT") {
      if (!n) fail(line, "attribute \"" + name + "\" takes a number");
      if (d.type != "FLOAT" && !n->whole) fail(line, "attribute \"" + name + "\" takes an integer");
      const bool bounded = d.minimum.value != d.maximum.value;  // [0|0] and the like: no limits
      if (bounded && !(d.minimum.value <= n->value && n->value <= d.maximum.value))
        fail(line, "value " + format_value(*n) + " of attribute \"" + name + "\" is outside its range [" + format_value(d.minimum) +
                       ", " + format_value(d.maximum) + "]");
    } else if (d.type == "STRING") {
      if (n) fail(line, "attribute \"" + name + "\" takes a string");
    } else if (!n) {
      if (std::find(d.choices.begin(), d.choices.end(), std::get<std::string>(v)) == d.choices.end())
        fail(line, "\"" + std::get<std::string>(v) + "\" is not one of the values of attribute \"" + name + "\"");
    } else if (!n->whole || n->integer < 0 || n->integer >= static_cast<long long>(d.choices.size())) {
      fail(line, "value " + format_value(*n) + " is not an index into the values of attribute \"" + name + "\"");
    }
  }
  static std::uint32_t cycle_time(const internal::Value& v, int line) {
    const Number* n = std::get_if<Number>(&v);
    if (!n || !n->whole || n->integer < 0 || n->integer >= (1LL << 32))
      fail(line, "GenMsgCycleTime must be a whole number of milliseconds (0..4294967295)");
    return static_cast<std::uint32_t>(n->integer);
  }

  void resolve(const Statement& st) {
    switch (st.kind) {
      case Statement::Kind::attr_default:
        check_attribute_value(st.name, definition(st.name, st.line), st.value, st.line);
        if (st.name == "GenMsgCycleTime") default_cycle_ = cycle_time(st.value, st.line);
        break;
      case Statement::Kind::attr_value: {
        const internal::AttributeDef& d = definition(st.name, st.line);
        if (d.object_kind != st.object_kind)
          fail(st.line, "attribute \"" + st.name + "\" is defined for " + (d.object_kind.empty() ? "the network" : d.object_kind) +
                            ", not " + (st.object_kind.empty() ? "the network" : st.object_kind));
        check_attribute_value(st.name, d, st.value, st.line);
        if (st.object_kind == "BO_") {
          auto [m, index] = message(st.message_id, st.line, "BA_");
          if (m && st.name == "GenMsgCycleTime") cycle_[index] = cycle_time(st.value, st.line);
        } else if (st.object_kind == "SG_") {
          signal(message(st.message_id, st.line, "BA_").first, st.signal, st.line, "BA_");
        }
        break;
      }
      case Statement::Kind::values:
        signal(message(st.message_id, st.line, "VAL_").first, st.signal, st.line, "VAL_");
        break;
      case Statement::Kind::value_type: {
        auto [m, index] = message(st.message_id, st.line, "SIG_VALTYPE_");
        RawSignal* r = signal(m, st.signal, st.line, "SIG_VALTYPE_");
        if (r && generated(index) && st.value_type != 0)
          fail(st.line, "signal " + st.signal + ": IEEE float signals (SIG_VALTYPE_ " + std::to_string(st.value_type) +
                            ") are not supported");
        break;
      }
      case Statement::Kind::mux_values: {
        auto [m, index] = message(st.message_id, st.line, "SG_MUL_VAL_");
        RawSignal* r = signal(m, st.signal, st.line, "SG_MUL_VAL_");
        if (!r || !signal(m, st.multiplexor, st.line, "SG_MUL_VAL_") || !generated(index)) break;
        const Signal* multiplexor = nullptr;
        for (const RawSignal& s : m->signals)
          if (s.signal.mux == Signal::Mux::multiplexor) multiplexor = &s.signal;
        if (r->signal.mux != Signal::Mux::multiplexed)
          fail(st.line, "SG_MUL_VAL_: signal " + st.signal + " is not multiplexed (m<N>)");
        if (!multiplexor || multiplexor->name != st.multiplexor)
          fail(st.line, "SG_MUL_VAL_: " + st.multiplexor + " is not the multiplexor (M) of message " + m->name +
                            "; extended multiplexing is not supported");
        r->signal.mux_ranges.assign(st.ranges.begin(), st.ranges.end());
        r->signal.mux_value = st.ranges.front().first;
        break;
      }
    }
  }

  Document& doc_;
  std::string path_;
  std::map<std::string, int> nodes_;
  std::set<std::string> unknown_nodes_;
  std::map<std::uint64_t, std::size_t> by_id_;
  std::set<std::size_t> left_out_;
  std::set<std::pair<int, std::string>> left_out_signals_;  // (message line, signal name)
  std::map<std::size_t, std::uint32_t> cycle_;
  std::uint32_t default_cycle_ = 0;
  std::vector<std::pair<int, std::string>> warnings_;
};

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

Database parse(std::string_view text, std::string path) {
  try {
    Document doc = internal::parse_document(internal::tokenize(text));
    return Checker(doc, path).run();
  } catch (const ParseError& e) {
    throw Error(path + ":" + std::to_string(e.line) + ": " + e.reason);
  }
}

Database read(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ":0: cannot read the file");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return parse(as_utf8(bytes.str()), file.string());  // UTF-8, or Latin-1 (cp1252) as UTF-8
}

bool extract_raw(const Signal& s, const std::uint8_t* data, int len, std::int64_t& raw) {
  std::uint64_t bits = 0;
  const std::vector<int> where = frame_bits(s);
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
  const std::vector<int> where = frame_bits(s);
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
