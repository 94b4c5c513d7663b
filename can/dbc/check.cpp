// The checks that decide what a DBC file's frames are: what stops (one line, FILE:LINE: reason) and
// what is read past with a warning, in the order the statements come, so the same file gives the
// same warnings in the same order on every route. Their words are the Python generator's that this
// replaced, word for word: tests and users match them.
#include "can/dbc/internal/check.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <map>
#include <set>

#include "can/dbc/internal/exact.hpp"

namespace lptn::dbc::internal {

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

namespace {

constexpr std::uint64_t kExtendedFlag = 0x80000000u;
constexpr std::uint64_t kIndependentSignalsId = 0xC0000000u;  // Vector's pseudo message: not a frame
constexpr long long kFdLengths[] = {12, 16, 20, 24, 32, 48, 64};

std::string hex(std::uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "0x%llX", static_cast<unsigned long long>(v));
  return buf;
}
// A statement's message id as written: integer() read it as a (possibly negative) long long.
std::string id_text(std::uint64_t id) { return std::to_string(static_cast<long long>(id)); }


// What `length` bits hold, up to 2^64 - 1: exact in a long double.
std::pair<long double, long double> raw_limits(const Signal& s) {
  const long double span = static_cast<long double>(std::uint64_t{1} << (s.length - 1)) * 2.0L;  // 2^length
  if (s.is_signed) return {-span / 2, span / 2 - 1};
  return {0.0L, span - 1};
}
std::string whole(long double v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.0Lf", v);
  return buf;
}
std::string format_ranges(const std::vector<std::pair<std::int64_t, std::int64_t>>& ranges) {
  std::string out;
  for (const auto& [low, high] : ranges) {
    if (!out.empty()) out += ", ";
    out += low == high ? std::to_string(low) : std::to_string(low) + ".." + std::to_string(high);
  }
  return out;
}
std::string format_value(const Number& n) {
  if (n.whole) return std::to_string(n.integer);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", n.value);
  return buf;
}

struct Checked {
  explicit Checked(RawMessage* m) : raw(m) {}
  RawMessage* raw;
  bool left_out = false;       // no CAN frame can have its id
  bool bare_extended = false;  // an id above 0x7FF without the flag, taken as extended
  std::vector<RawSignal> left_out_signals;
  std::optional<std::uint32_t> cycle;
  std::vector<std::string> transmitters;
  std::string comment;

  bool is_frame() const { return raw->dbc_id != kIndependentSignalsId; }
  bool generated() const { return is_frame() && !left_out; }
  bool extended() const { return (raw->dbc_id & kExtendedFlag) || bare_extended; }
  std::uint64_t can_id() const { return raw->dbc_id & ~kExtendedFlag; }
  const Signal* multiplexor() const {
    for (const RawSignal& r : raw->signals)
      if (r.signal.mux == Signal::Mux::multiplexor) return &r.signal;
    return nullptr;
  }
};

class Checker {
 public:
  Checker(Document& doc, std::string path, std::string_view node) : doc_(doc), path_(std::move(path)), node_(node) {
    for (RawMessage& m : doc_.messages) messages_.emplace_back(&m);
  }

  Database run() {
    for (const auto& [line, reason] : doc_.warnings) warn(line, reason);
    check_nodes();
    check_messages();
    for (const Statement& st : doc_.statements) resolve(st);
    for (Checked& m : messages_)
      if (m.generated()) check_layout(m);
    std::uint32_t default_cycle = 0;
    for (const Statement& st : doc_.statements)
      if (st.kind == Statement::Kind::attr_default && st.name == "GenMsgCycleTime") default_cycle = cycle_time(st.value, st.line);
    if (doc_.nodes_line && node_ != kNoNode &&
        std::none_of(doc_.nodes.begin(), doc_.nodes.end(), [&](const auto& n) { return n.first == node_; }))
      fail(*doc_.nodes_line, "node " + std::string(node_) + " (--node) is not in BU_");
    return database(default_cycle);
  }

 private:
  [[noreturn]] static void fail(int line, const std::string& reason) { throw ParseError{line, reason}; }
  void warn(int line, std::string reason) { warnings_.push_back({line, std::move(reason)}); }

  Database database(std::uint32_t default_cycle) {
    Database db;
    db.path = path_;
    for (Checked& c : messages_) {
      if (!c.generated()) continue;
      Message m;
      m.name = c.raw->name;
      m.sender = c.raw->sender;
      m.id = static_cast<std::uint32_t>(c.can_id());
      m.extended = c.extended();
      m.length = static_cast<int>(c.raw->dlc);
      m.line = c.raw->line;
      m.cycle_ms = c.cycle ? *c.cycle : default_cycle;
      m.comment = c.comment;
      m.transmitters = c.transmitters;
      for (RawSignal& s : c.raw->signals) m.signals.push_back(std::move(s.signal));
      db.messages.push_back(std::move(m));
    }
    db.comment = comment_;
    db.node_comments = node_comments_;
    std::stable_sort(warnings_.begin(), warnings_.end(), [](const Warning& a, const Warning& b) { return a.line < b.line; });
    db.warnings = std::move(warnings_);
    return db;
  }

  void check_nodes() {
    if (!doc_.nodes_line) warn(1, "the file has no BU_ section; senders and receivers are not checked");
    for (const auto& [name, line] : doc_.nodes) {
      if (auto it = nodes_.find(name); it != nodes_.end()) {
        warn(line, "node " + name + " is listed twice in BU_ (first on line " + std::to_string(it->second) + ")");
        continue;
      }
      nodes_.emplace(name, line);
    }
  }
  // One warning per unknown node, where the file first names it.
  void check_node(const std::string& name, int line, const std::string& role) {
    if (name == kNoNode || nodes_.count(name) || !doc_.nodes_line) return;
    if (unknown_nodes_.insert(name).second) warn(line, role + " '" + name + "' is not a node in BU_");
  }

  void check_messages() {
    std::map<std::string, const RawMessage*> by_name;
    std::map<std::pair<bool, std::uint64_t>, const RawMessage*> by_frame;
    for (std::size_t i = 0; i < messages_.size(); ++i) {
      Checked& c = messages_[i];
      RawMessage& m = *c.raw;
      if (auto it = by_id_.find(m.dbc_id); it != by_id_.end()) {
        const RawMessage& first = *messages_[it->second].raw;
        fail(m.line, "message id " + std::to_string(m.dbc_id) + " (" + hex(c.can_id()) + ") is already used by " + first.name +
                         " on line " + std::to_string(first.line));
      }
      by_id_.emplace(m.dbc_id, i);
      if (!c.is_frame()) continue;
      if (auto it = by_name.find(m.name); it != by_name.end())
        fail(m.line, "message name " + m.name + " is already used on line " + std::to_string(it->second->line));
      by_name.emplace(m.name, &m);
      check_id(c);
      if (c.left_out) continue;
      const auto key = std::pair{c.extended(), c.can_id()};
      if (auto it = by_frame.find(key); it != by_frame.end())
        fail(m.line, "message " + m.name + ": " + (c.extended() ? "extended" : "standard") + " id " + hex(c.can_id()) +
                         " is already used by " + it->second->name + " on line " + std::to_string(it->second->line));
      by_frame.emplace(key, &m);
      check_message(c);
    }
  }

  // Flagged ids fit in 29 bits; a bare id above 0x7FF is taken as extended (tools write them so); an
  // id no CAN frame can have leaves its message out.
  void check_id(Checked& c) {
    const RawMessage& m = *c.raw;
    const std::string where = "message " + m.name;
    if (m.dbc_id & kExtendedFlag) {
      if (c.can_id() > 0x1FFFFFFF) {
        c.left_out = true;
        warn(m.line, where + ": extended id " + hex(c.can_id()) + " does not fit in 29 bits; no CAN frame has it, so the message is left out");
      }
    } else if (c.can_id() > 0x1FFFFFFF) {
      c.left_out = true;
      warn(m.line, where + ": id " + std::to_string(m.dbc_id) + " (" + hex(m.dbc_id) +
                       ") fits neither 11 nor 29 bits and has no extended flag (0x80000000); no CAN frame has it, so the message is left out");
    } else if (c.can_id() > 0x7FF) {
      c.bare_extended = true;
      warn(m.line, where + ": id " + hex(c.can_id()) +
                       " does not fit in 11 bits and has no extended flag (0x80000000); taken as a 29-bit extended id");
    }
  }

  void check_message(Checked& c) {
    RawMessage& m = *c.raw;
    const std::string where = "message " + m.name;
    const std::string dlc = std::to_string(m.dlc);
    if (m.dlc > 64) fail(m.line, where + ": length " + dlc + " is more than 64 bytes, CAN FD's longest frame");
    if (m.dlc > 8 && std::find(std::begin(kFdLengths), std::end(kFdLengths), m.dlc) == std::end(kFdLengths)) {
      const long long fd = *std::find_if(std::begin(kFdLengths), std::end(kFdLengths), [&](long long l) { return l > m.dlc; });
      warn(m.line, where + ": length " + dlc + " is not a CAN FD frame length (a frame carrying it is " + std::to_string(fd) +
                       " bytes long); " + dlc + " bytes are packed and unpacked");
    }
    check_node(m.sender, m.line, where + ": sender");
    if (m.signals.empty())
      warn(m.line, where + " has no signals; its struct " + (m.dlc ? "packs " + dlc + " zero bytes" : std::string("has no data")));
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
        c.left_out_signals.push_back(std::move(r));
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
        fail(r.signal.line, "signal " + r.signal.name + " is multiplexed (m" + std::to_string(r.signal.mux_ranges.front().first) +
                                ") but message " + m.name + " has no multiplexor (M)");
  }

  // False: the signal lies outside its frame and the node neither sends nor receives it: left out.
  bool check_signal(const RawMessage& m, RawSignal& r) {
    Signal& s = r.signal;
    const std::string where = "signal " + s.name;
    if (s.length < 1 || s.length > 64) fail(s.line, where + ": length " + std::to_string(s.length) + " is not in 1..64");
    if (s.factor == 0) fail(s.line, where + ": factor 0 (every raw value would decode to the offset)");
    for (const std::string& receiver : s.receivers) check_node(receiver, s.line, where + ": receiver");
    const std::vector<int> bits = frame_bits(s);
    if (*std::max_element(bits.begin(), bits.end()) >= 8 * m.dlc) {
      // The file contradicts itself (the length or the layout is wrong) and nothing tells which. The
      // node the reading is for cannot do without a signal it sends or receives: an error. A signal
      // only other nodes use is left out, with a warning.
      const std::string overflow = where + " (" + (s.big_endian ? "big-endian" : "little-endian") + ", start bit " +
                                   std::to_string(s.start) + ", " + std::to_string(s.length) + " bits) overflows its " +
                                   std::to_string(m.dlc) + "-byte frame";
      if (node_ != kNoNode && (node_ == m.sender || std::find(s.receivers.begin(), s.receivers.end(), node_) != s.receivers.end()))
        fail(s.line, overflow);
      warn(s.line, overflow + "; " + std::string(node_) + " neither sends nor receives it, so it is left out");
      return false;
    }
    check_range(r);
    return true;
  }

  // A range that cannot be right leaves decoding alone: a warning, and the range is ignored.
  void check_range(RawSignal& r) {
    Signal& s = r.signal;
    const std::string where = "signal " + s.name + ": range [" + r.minimum.text + "|" + r.maximum.text + "]";
    const auto [low, high] = raw_limits(s);
    const ExactRange e = exact_range(r.factor, r.offset, r.minimum, r.maximum, low, high);
    if (e.min_above_max) {
      s.range_ignored = true;
      warn(s.line, where + ": minimum " + r.minimum.text + " is greater than maximum " + r.maximum.text +
                       "; the range is ignored (every raw value is in range)");
      return;
    }
    if (e.no_range) return;
    if (e.exceeds_bits)
      warn(s.line, where + " needs raw values " + e.low_text + ".." + e.high_text + " but " + std::to_string(s.length) + " " +
                       (s.is_signed ? "signed" : "unsigned") + " bits cannot represent them (they hold " + whole(low) + ".." +
                       whole(high) + "); the range is checked within what the bits hold");
    if (e.holds_no_value) {
      s.range_ignored = true;
      warn(s.line, where + " contains no raw value the signal can hold; the range is ignored (every raw value is in range)");
      return;
    }
    s.raw_range = Signal::RawRange{e.low, e.high};
  }

  void check_layout(Checked& c) {
    const RawMessage& m = *c.raw;
    if (const Signal* mux = c.multiplexor()) check_mux_values(m, *mux);
    std::map<int, std::vector<const Signal*>> owners;
    for (const RawSignal& r : m.signals) {
      const Signal& s = r.signal;
      std::vector<std::pair<std::string, int>> overlapped;  // first shared bit per signal, in the order met
      for (const int bit : frame_bits(s)) {
        for (const Signal* other : owners[bit]) {
          if (!mux_values_meet(s, *other)) continue;
          if (std::none_of(overlapped.begin(), overlapped.end(), [&](const auto& o) { return o.first == other->name; }))
            overlapped.emplace_back(other->name, bit);
        }
        owners[bit].push_back(&s);
      }
      if (overlapped.empty()) continue;
      // Each signal still reads its own bits; only a frame packed with both is ambiguous.
      std::string others;
      for (const auto& [name, bit] : overlapped)
        others += (others.empty() ? "" : ", ") + name + " (frame bit " + std::to_string(bit) + ")";
      warn(s.line, "signal " + s.name + " overlaps signal" + (overlapped.size() > 1 ? "s " : " ") + others + " in message " + m.name +
                       "; each unpacks from the shared bits, pack() ORs them together");
    }
  }
  static bool mux_values_meet(const Signal& a, const Signal& b) {
    if (a.mux != Signal::Mux::multiplexed || b.mux != Signal::Mux::multiplexed) return true;
    for (const auto& [al, ah] : a.mux_ranges)
      for (const auto& [bl, bh] : b.mux_ranges)
        if (al <= bh && bl <= ah) return true;
    return false;
  }
  void check_mux_values(const RawMessage& m, const Signal& mux) {
    // Not a structured binding: clang 14 (the fuzz preset) cannot capture one in the lambda below.
    const std::pair<long double, long double> limits = raw_limits(mux);
    const long double low = limits.first, high = limits.second;
    for (const RawSignal& r : m.signals) {
      const Signal& s = r.signal;
      if (s.mux != Signal::Mux::multiplexed) continue;
      const bool never = std::all_of(s.mux_ranges.begin(), s.mux_ranges.end(), [&](const auto& range) {
        return static_cast<long double>(range.second) < low || static_cast<long double>(range.first) > high;
      });
      if (never)
        warn(s.line, "signal " + s.name + ": multiplexor " + mux.name + " (" + std::to_string(mux.length) + " bits, raw " + whole(low) +
                         ".." + whole(high) + ") never takes " + format_ranges(s.mux_ranges) + "; the signal is never in the frame");
    }
  }

  // -- statements that name other objects: one about a message or signal the file does not define
  // describes nothing on the bus, and is read past with a warning.
  Checked* message(std::uint64_t id, int line, const std::string& statement) {
    auto it = by_id_.find(id);
    if (it == by_id_.end()) {
      warn(line, "no message has id " + id_text(id) + "; the " + statement + " is ignored");
      return nullptr;
    }
    return &messages_[it->second];
  }
  struct Found {
    Checked* message = nullptr;
    Signal* signal = nullptr;
    bool left_out = false;
  };
  Found signal(std::uint64_t id, const std::string& name, int line, const std::string& statement) {
    Checked* m = message(id, line, statement);
    if (!m) return {};
    for (RawSignal& r : m->raw->signals)
      if (r.signal.name == name) return {m, &r.signal, false};
    for (RawSignal& r : m->left_out_signals)
      if (r.signal.name == name) return {m, &r.signal, true};
    warn(line, "message " + m->raw->name + " has no signal " + name + "; the " + statement + " is ignored");
    return {};
  }
  // A second statement for the same thing: the later one is used.
  void once(const std::string& what, const std::string& key, int line) {
    if (auto it = seen_.find(key); it != seen_.end())
      warn(line, "second " + what + " (the first is on line " + std::to_string(it->second) + "); this one is used");
    seen_[key] = line;
  }

  const AttributeDef& definition(const std::string& name, int line) {
    auto it = doc_.attribute_defs.find(name);
    if (it == doc_.attribute_defs.end()) fail(line, "attribute \"" + name + "\" has no BA_DEF_");
    return it->second;
  }
  static void check_attribute_value(const std::string& name, const AttributeDef& d, const Value& v, int line) {
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
  static std::uint32_t cycle_time(const Value& v, int line) {
    const Number* n = std::get_if<Number>(&v);
    if (!n || !n->whole || n->integer < 0 || n->integer >= (1LL << 32))
      fail(line, "GenMsgCycleTime must be a whole number of milliseconds (0..4294967295)");
    return static_cast<std::uint32_t>(n->integer);
  }
  // How a statement names its object in a warning, as Python printed the key: None, 256, (256, 'Speed').
  static std::string key_text(const Statement& st) {
    if (st.object_kind.empty()) return "None";
    if (st.object_kind == "BO_") return id_text(st.message_id);
    if (st.object_kind == "SG_") return "(" + id_text(st.message_id) + ", '" + st.signal + "')";
    return st.signal;
  }
  static std::string key(const Statement& st) {
    return st.object_kind + '\x1f' + (st.object_kind == "BO_" || st.object_kind == "SG_" ? id_text(st.message_id) : "") + '\x1f' +
           st.signal;
  }

  void resolve(const Statement& st) {
    switch (st.kind) {
      case Statement::Kind::comment: resolve_comment(st); break;
      case Statement::Kind::attr_default:
        once("default for attribute \"" + st.name + "\"", "BA_DEF_DEF_\x1f" + st.name, st.line);
        check_attribute_value(st.name, definition(st.name, st.line), st.value, st.line);
        break;
      case Statement::Kind::attr_value: resolve_attr_value(st); break;
      case Statement::Kind::values: resolve_values(st); break;
      case Statement::Kind::value_type: {
        const Found f = signal(st.message_id, st.signal, st.line, "SIG_VALTYPE_");
        if (f.message && f.message->generated() && !f.left_out && st.value_type != 0)
          fail(st.line, "signal " + f.signal->name + ": IEEE float signals (SIG_VALTYPE_ " + std::to_string(st.value_type) +
                            ") are not supported");
        break;
      }
      case Statement::Kind::transmitters: {
        Checked* m = message(st.message_id, st.line, "BO_TX_BU_");
        if (!m) break;
        for (const std::string& node : st.nodes) check_node(node, st.line, "message " + m->raw->name + ": transmitter");
        m->transmitters.insert(m->transmitters.end(), st.nodes.begin(), st.nodes.end());
        break;
      }
      case Statement::Kind::mux_values: resolve_mux_values(st); break;
    }
  }
  void resolve_comment(const Statement& st) {
    std::string target = "the network";
    if (st.object_kind == "BU_") target = "node " + st.signal;
    if (st.object_kind == "BO_") target = "message " + id_text(st.message_id);
    if (st.object_kind == "SG_") target = "signal " + st.signal + " of message " + id_text(st.message_id);
    if (st.object_kind == "EV_") target = "environment variable " + st.signal;
    once("comment for " + target, "CM_\x1f" + key(st), st.line);
    if (st.object_kind.empty()) {
      comment_ = st.text;
    } else if (st.object_kind == "BU_") {
      check_node(st.signal, st.line, "CM_ BU_:");
      node_comments_[st.signal] = st.text;
    } else if (st.object_kind == "BO_") {
      if (Checked* m = message(st.message_id, st.line, "CM_")) m->comment = st.text;
    } else if (st.object_kind == "SG_") {
      if (Signal* s = signal(st.message_id, st.signal, st.line, "CM_").signal) s->comment = st.text;
    }
  }
  void resolve_attr_value(const Statement& st) {
    const AttributeDef& d = definition(st.name, st.line);
    if (d.object_kind != st.object_kind)
      fail(st.line, "attribute \"" + st.name + "\" is defined for " + (d.object_kind.empty() ? "the network" : d.object_kind) +
                        ", not " + (st.object_kind.empty() ? "the network" : st.object_kind));
    once("value of attribute \"" + st.name + "\" for " + st.object_kind + " " + key_text(st), "BA_\x1f" + st.name + '\x1f' + key(st),
         st.line);
    check_attribute_value(st.name, d, st.value, st.line);
    if (st.object_kind == "BU_") {
      check_node(st.signal, st.line, "BA_ BU_:");
    } else if (st.object_kind == "BO_") {
      Checked* m = message(st.message_id, st.line, "BA_");
      if (m && st.name == "GenMsgCycleTime") m->cycle = cycle_time(st.value, st.line);
    } else if (st.object_kind == "SG_") {
      signal(st.message_id, st.signal, st.line, "BA_");
    }
  }
  void resolve_values(const Statement& st) {
    once("VAL_ for signal " + st.signal, "VAL_\x1f" + id_text(st.message_id) + '\x1f' + st.signal, st.line);
    const Found f = signal(st.message_id, st.signal, st.line, "VAL_");
    if (!f.message || !f.message->generated() || f.left_out) return;  // never checked, nor generated
    Signal& s = *f.signal;
    const auto [low, high] = raw_limits(s);
    std::vector<std::pair<std::int64_t, std::string>> pairs;
    for (const auto& [raw, description] : st.pairs) {
      const auto r = static_cast<long double>(raw);
      if (low <= r && r <= high)
        pairs.emplace_back(raw, description);
      else
        warn(st.line, "VAL_ value " + std::to_string(raw) + " does not fit signal " + s.name + " (raw " + whole(low) + ".." + whole(high) +
                          "); it is left out of the enum");
    }
    s.values = std::move(pairs);
  }
  // SG_MUL_VAL_: the multiplexor values that carry a signal, for the message's only multiplexor
  // (what simple multiplexing writes; the m<N> value is replaced).
  void resolve_mux_values(const Statement& st) {
    once("SG_MUL_VAL_ for signal " + st.signal, "SG_MUL_VAL_\x1f" + id_text(st.message_id) + '\x1f' + st.signal, st.line);
    const Found f = signal(st.message_id, st.signal, st.line, "SG_MUL_VAL_");
    if (!f.message || !signal(st.message_id, st.multiplexor, st.line, "SG_MUL_VAL_").signal) return;
    if (!f.message->generated() || f.left_out) return;
    const Signal* mux = f.message->multiplexor();
    if (f.signal->mux != Signal::Mux::multiplexed) fail(st.line, "SG_MUL_VAL_: signal " + f.signal->name + " is not multiplexed (m<N>)");
    if (!mux || mux->name != st.multiplexor)
      fail(st.line, "SG_MUL_VAL_: " + st.multiplexor + " is not the multiplexor (M) of message " + f.message->raw->name +
                        "; extended multiplexing is not supported");
    f.signal->mux_ranges.assign(st.ranges.begin(), st.ranges.end());
    f.signal->mux_value = st.ranges.front().first;
  }

  Document& doc_;
  std::string path_;
  std::string_view node_;
  std::vector<Checked> messages_;
  std::map<std::string, int> nodes_;
  std::set<std::string> unknown_nodes_;
  std::map<std::uint64_t, std::size_t> by_id_;
  std::map<std::string, int> seen_;
  std::string comment_;
  std::map<std::string, std::string> node_comments_;
  std::vector<Warning> warnings_;
};

}  // namespace

Database check(Document& doc, const std::string& path, std::string_view node) { return Checker(doc, path, node).run(); }

}  // namespace lptn::dbc::internal
