#include "can/bus/bus_map.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>
#include <string_view>
#include <toml++/toml.h>

#include "can/bus/bus_vocabulary.hpp"
#include "lptn/firmware/e2e.hpp"

namespace lptn::bus {
namespace {

namespace fs = std::filesystem;

// The messages below are the words the Python glue generator used, word for word (tests/bus's
// check_bad_maps.py expects them); the build's generator reads maps with this same reader.

std::string one_line(std::string message) {
  std::replace_if(message.begin(), message.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  return message;
}

class Reader {
 public:
  explicit Reader(fs::path file) : file_(std::move(file)) {}

  [[noreturn]] void fail(std::uint32_t line, const std::string& reason) const {
    throw MapError(one_line(file_.string() + ":" + std::to_string(line) + ": " + reason));
  }
  static std::uint32_t line_of(const toml::node& n) { return std::max<std::uint32_t>(1, n.source().begin.line); }

  std::string string(const toml::table& t, std::string_view key) const {
    const toml::node* n = t.get(key);
    const auto* s = n ? n->as_string() : nullptr;
    if (!s || s->get().empty()) fail(n ? line_of(*n) : line_of(t), std::string(key) + " must be a non-empty string");
    return s->get();
  }
  double number(const toml::table& t, std::string_view key, double fallback) const {
    const toml::node* n = t.get(key);
    if (!n) return fallback;
    if (const auto* i = n->as_integer()) return static_cast<double>(i->get());
    if (const auto* f = n->as_floating_point()) return f->get();
    fail(line_of(*n), std::string(key) + " must be a number");
  }
  const fs::path& file() const { return file_; }

 private:
  fs::path file_;
};

// A table's entries in the order the file writes them (toml++ keeps them sorted by key): the first
// bad entry is the one refused, and the inputs come in the map's order, as the generated glue lists
// them.
std::vector<std::pair<std::string, const toml::node*>> in_file_order(const toml::table& t) {
  std::vector<std::pair<std::string, const toml::node*>> entries;
  for (const auto& [key, node] : t) entries.emplace_back(std::string(key.str()), &node);
  std::stable_sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
    const auto& x = a.second->source().begin;
    const auto& y = b.second->source().begin;
    return x.line != y.line ? x.line < y.line : x.column < y.column;
  });
  return entries;
}

const InputWord* input_word(std::string_view column) {
  for (const InputWord& w : kInputWords)
    if (column == w.column) return &w;
  return nullptr;
}

std::string input_list() {
  std::string s;
  for (const InputWord& w : kInputWords) s += (s.empty() ? "" : ", ") + std::string(w.column);
  return s;
}

std::string trimmed(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return std::string(s);
}

const UnitWord* unit_word(std::string_view unit) {
  const std::string u = trimmed(unit);
  for (const UnitWord& w : kUnitWords)
    if (u == w.spelling) return &w;
  return nullptr;
}

std::string g6(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// Empty if the signal's unit can carry the input; else why not, one clause.
std::string unit_problem(const std::string& unit, std::string_view canonical, double scale, double offset) {
  const UnitWord* w = unit_word(unit);
  if (!w) return {};
  if (canonical != w->canonical) return "its unit '" + unit + "' is not one of " + std::string(canonical);
  const bool scale_ok = std::fabs(scale - w->factor) <= kUnitTolerance * std::fabs(w->factor);
  const bool offset_ok = std::fabs(offset - w->offset) <= kUnitTolerance * std::max(1.0, std::fabs(w->offset));
  if (scale_ok && offset_ok) return {};
  return "its unit is '" + unit + "': to give " + std::string(canonical) + " it needs scale = " + g6(w->factor) +
         " and offset = " + g6(w->offset) + ", not scale = " + g6(scale) + " and offset = " + g6(offset);
}

// The raw value's limits for encoding: round to nearest, saturate.
std::int64_t raw_of(const lptn::dbc::Signal& s, double physical) { return lptn::dbc::to_raw(s, physical); }

std::string hex(std::uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%X", v);
  return buf;
}

// [outputs]: the CAN id of each of the estimator's frames; `defaults` (lptn.dbc's) where the map
// gives none; above 0x7FF an extended one. None may be another frame's.
std::array<fw::OutputId, fw::kMaxOutputFrames> read_output_ids(const Reader& r, const toml::table& doc,
                                                               const std::vector<MappedMessage>& uses,
                                                               const std::array<fw::OutputId, fw::kMaxOutputFrames>& defaults) {
  static_assert(std::size(kOutputFrameNames) == static_cast<std::size_t>(fw::kMaxOutputFrames));
  std::array<fw::OutputId, fw::kMaxOutputFrames> ids = defaults;
  const toml::table* outputs = nullptr;
  std::uint32_t table_line = 1;
  if (const toml::node* node = doc.get("outputs")) {
    outputs = node->as_table();
    if (!outputs) r.fail(Reader::line_of(*node), "outputs must be a table [outputs]");
    table_line = Reader::line_of(*node);
  }
  const auto index_of = [](std::string_view name) {
    for (int k = 0; k < fw::kMaxOutputFrames; ++k)
      if (name == kOutputFrameNames[k]) return k;
    return -1;
  };
  if (outputs) {
    for (const auto& [key, node_ptr] : in_file_order(*outputs)) {
      const toml::node& node = *node_ptr;
      const std::string name(key);
      const int k = index_of(name);
      if (k < 0) {
        std::string names;
        for (const char* f : kOutputFrameNames) names += (names.empty() ? "" : ", ") + std::string(f);
        r.fail(Reader::line_of(node), "[outputs]: unknown key '" + name + "' (" + names + ")");
      }
      const auto* i = node.as_integer();
      if (!i || i->get() < 0 || i->get() > 0x1FFFFFFF)
        r.fail(Reader::line_of(node), "[outputs] " + name + ": a CAN id, 0..0x1FFFFFFF (above 0x7FF an extended one)");
      ids[static_cast<std::size_t>(k)] = {static_cast<std::uint32_t>(i->get()), i->get() > 0x7FF};
    }
  }
  std::vector<std::pair<fw::OutputId, std::string>> taken;
  for (const MappedMessage& u : uses) taken.push_back({{u.message->id, u.message->extended}, u.message->name});
  for (int k = 0; k < fw::kMaxOutputFrames; ++k) {
    const std::string name = kOutputFrameNames[k];
    const fw::OutputId id = ids[static_cast<std::size_t>(k)];
    const toml::node* given = outputs ? outputs->get(name) : nullptr;
    for (const auto& [other, owner] : taken)
      if (other.id == id.id && other.extended == id.extended)
        r.fail(given ? Reader::line_of(*given) : table_line, "[outputs] " + name + ": id " + hex(id.id) + " is " + owner +
                                                                 "'s too; give " + name + " another id in [outputs]");
    taken.push_back({id, name});
  }
  return ids;
}

}  // namespace

std::unique_ptr<BusMap> BusMap::read(const fs::path& map_file, const std::array<fw::OutputId, fw::kMaxOutputFrames>& default_outputs) {
  Reader r(map_file);
  toml::table doc;
  try {
    doc = toml::parse_file(map_file.string());
  } catch (const toml::parse_error& e) {
    const std::string_view d = e.description();
    if (d.find("could not be opened") != std::string_view::npos || d.find("File could not") != std::string_view::npos)
      throw MapError(map_file.string() + ":0: cannot read the file");
    r.fail(std::max<std::uint32_t>(1, e.source().begin.line), "not TOML: " + std::string(d));
  }
  for (const auto& [key, node] : doc)
    if (key != "dbc" && key != "inputs" && key != "messages" && key != "outputs")
      r.fail(Reader::line_of(node), "unknown key '" + std::string(key.str()) + "' (dbc, [inputs.NAME], [messages.NAME], [outputs])");
  if (!doc.get("dbc")) r.fail(1, "dbc = \"converter.dbc\" is missing");

  auto map = std::unique_ptr<BusMap>(new BusMap());
  map->file_ = map_file;
  const fs::path dbc_file = fs::absolute(map_file).parent_path() / r.string(doc, "dbc");
  try {
    map->dbc_ = lptn::dbc::read(dbc_file);
  } catch (const lptn::dbc::Error& e) {
    r.fail(Reader::line_of(*doc.get("dbc")), std::string("dbc: ") + e.what());
  }
  const std::string dbc_name = dbc_file.filename().string();

  std::vector<MappedMessage> uses;  // in the map's order, sorted into the DBC's below
  auto use_of = [&](const lptn::dbc::Message* m) -> MappedMessage& {
    for (MappedMessage& u : uses)
      if (u.message == m) return u;
    MappedMessage u{};
    u.message = m;
    u.max_delta_counter = static_cast<unsigned>(kDefaultMaxDeltaCounter);
    u.cycle_ms = m->cycle_ms;
    uses.push_back(std::move(u));
    return uses.back();
  };
  std::set<std::string> columns;
  if (const toml::node* inputs_node = doc.get("inputs")) {
    const toml::table* inputs = inputs_node->as_table();
    if (!inputs) r.fail(Reader::line_of(*inputs_node), "inputs must be tables [inputs.NAME]");
    for (const auto& [key, node_ptr] : in_file_order(*inputs)) {
      const toml::node& node = *node_ptr;
      const std::string column(key);
      const std::string table = "inputs." + column;
      const InputWord* word = input_word(column);
      if (!word) r.fail(Reader::line_of(node), "[" + table + "]: unknown input '" + column + "' (one of " + input_list() + ")");
      const toml::table* entry = node.as_table();
      if (!entry) r.fail(Reader::line_of(node), "[" + table + "] must be a table");
      for (const auto& [k, v] : *entry)
        if (k != "message" && k != "signal" && k != "scale" && k != "offset")
          r.fail(Reader::line_of(v), "[" + table + "]: unknown key '" + std::string(k.str()) +
                                         "' (message, signal, scale, offset)");
      for (const char* k : {"message", "signal"})
        if (!entry->get(k)) r.fail(Reader::line_of(*entry), "[" + table + "]: " + k + " is missing");
      const std::string name = r.string(*entry, "message");
      const lptn::dbc::Message* message = map->dbc_.find(name);
      if (!message) r.fail(Reader::line_of(*entry->get("message")), "[" + table + "] message: " + name +
                                                                         " is not a message of " + dbc_name);
      const std::string signal_name = r.string(*entry, "signal");
      const std::uint32_t signal_line = Reader::line_of(*entry->get("signal"));
      const lptn::dbc::Signal* signal = message->find(signal_name);
      if (!signal) r.fail(signal_line, "[" + table + "] signal: " + name + " has no signal " + signal_name);
      if (signal->mux == lptn::dbc::Signal::Mux::multiplexor)
        r.fail(signal_line, "[" + table + "] signal: " + signal_name + " is " + name + "'s multiplexor");
      if (signal->is_float)
        r.fail(signal_line, "[" + table + "] signal: " + signal_name + " is an IEEE float signal, which lptn does not decode");
      const double scale = r.number(*entry, "scale", 1.0);
      const double offset = r.number(*entry, "offset", 0.0);
      if (scale == 0.0)
        r.fail(Reader::line_of(*entry->get("scale")), "[" + table + "] scale: 0 would make the input a constant");
      const std::string problem = unit_problem(signal->unit, word->unit, scale, offset);
      if (!problem.empty())
        r.fail(signal_line, "[" + table + "] signal: " + name + "." + signal_name + " cannot be " + column + ": " + problem);
      if (!unit_word(signal->unit))
        map->warnings_.push_back(map_file.string() + ":" + std::to_string(signal_line) + ": warning: [" + table + "]: " +
                                 name + "." + signal_name + "'s unit '" + signal->unit +
                                 "' is not one lptn knows; taken as " + word->unit + " times scale plus offset");
      MappedMessage& use = use_of(message);
      use.inputs.push_back({word->input, column, signal, scale, offset});
      use.carried = static_cast<fw::InputMask>(use.carried | fw::bit(word->input));
      columns.insert(column);
    }
  }
  for (const InputWord& w : kInputWords)
    if (w.required && !columns.count(w.column))
      r.fail(1, "[inputs." + std::string(w.column) + "] is missing: the estimator cannot run without it");

  if (const toml::node* messages_node = doc.get("messages")) {
    const toml::table* messages = messages_node->as_table();
    if (!messages) r.fail(Reader::line_of(*messages_node), "messages must be tables [messages.NAME]");
    for (const auto& [key, node_ptr] : in_file_order(*messages)) {
      const toml::node& node = *node_ptr;
      const std::string name(key);
      const std::string table = "messages." + name;
      const lptn::dbc::Message* message = map->dbc_.find(name);
      auto used = std::find_if(uses.begin(), uses.end(), [&](const MappedMessage& u) { return u.message == message; });
      if (!message || used == uses.end()) r.fail(Reader::line_of(node), "[" + table + "]: " + name + " carries no input of this map");
      const toml::table* entry = node.as_table();
      if (!entry) r.fail(Reader::line_of(node), "[" + table + "] must be a table");
      for (const auto& [k, v] : *entry)
        if (k != "alive_counter" && k != "max_delta_counter" && k != "crc" && k != "data_id" && k != "cycle_ms")
          r.fail(Reader::line_of(v), "[" + table + "]: unknown key '" + std::string(k.str()) +
                                         "' (alive_counter, max_delta_counter, crc, data_id, cycle_ms)");
      if (entry->get("alive_counter")) {
        const std::string counter = r.string(*entry, "alive_counter");
        const std::uint32_t line = Reader::line_of(*entry->get("alive_counter"));
        const lptn::dbc::Signal* s = message->find(counter);
        if (!s) r.fail(line, "[" + table + "] alive_counter: " + name + " has no signal " + counter);
        if (s->mux == lptn::dbc::Signal::Mux::multiplexed || s->is_signed || s->length > 8 || s->factor != 1.0 || s->offset != 0.0)
          r.fail(line, "[" + table + "] alive_counter: " + counter +
                           " is no counter (unsigned, 1 to 8 bits, factor 1, offset 0, in every frame)");
        used->counter = s;
      }
      if (const toml::node* delta = entry->get("max_delta_counter")) {
        if (!used->counter) r.fail(Reader::line_of(*delta), "[" + table + "] max_delta_counter: there is no alive_counter");
        const auto* i = delta->as_integer();
        const long long top = (1ll << used->counter->length) - 1;
        if (!i || i->get() < 1 || i->get() > top)
          r.fail(Reader::line_of(*delta), "[" + table + "] max_delta_counter: a whole number from 1 to " + std::to_string(top));
        used->max_delta_counter = static_cast<unsigned>(i->get());
      }
      if (entry->get("crc")) {
        const std::string crc = r.string(*entry, "crc");
        const std::uint32_t line = Reader::line_of(*entry->get("crc"));
        const lptn::dbc::Signal* s = message->find(crc);
        if (!s) r.fail(line, "[" + table + "] crc: " + name + " has no signal " + crc);
        const bool aligned = s->start % 8 == (s->big_endian ? 7 : 0);
        if (s->mux == lptn::dbc::Signal::Mux::multiplexed || s->is_signed || s->length != 8 || !aligned || s->factor != 1.0 ||
            s->offset != 0.0)
          r.fail(line, "[" + table + "] crc: " + crc +
                           " is no CRC-8 (unsigned, 8 bits, one whole byte, factor 1, offset 0, in every frame)");
        if (!entry->get("data_id")) r.fail(line, "[" + table + "] crc: data_id (0..65535) is missing");
        used->crc = s;
        used->crc_byte = s->start / 8;
      }
      if (const toml::node* id = entry->get("data_id")) {
        if (!used->crc) r.fail(Reader::line_of(*id), "[" + table + "] data_id: there is no crc");
        const auto* i = id->as_integer();
        if (!i || i->get() < 0 || i->get() > 0xFFFF) r.fail(Reader::line_of(*id), "[" + table + "] data_id: a whole number, 0..65535");
        used->data_id = static_cast<std::uint16_t>(i->get());
      }
      if (const toml::node* cycle = entry->get("cycle_ms")) {
        const auto* i = cycle->as_integer();
        if (!i || i->get() < 1 || i->get() > 60000)
          r.fail(Reader::line_of(*cycle), "[" + table + "] cycle_ms: a whole number of ms, 1..60000");
        used->cycle_ms = static_cast<std::uint32_t>(i->get());
      }
    }
  }
  for (const MappedMessage& u : uses)
    if (!u.cycle_ms)
      r.fail(Reader::line_of(*doc.get("inputs")->as_table()->get(u.inputs.front().column)->as_table()->get("message")),
             u.message->name + " has no cycle time in the DBC (GenMsgCycleTime): give cycle_ms in [messages." +
                 u.message->name + "]");
  if (uses.size() > static_cast<std::size_t>(fw::kMaxBusMessages))
    r.fail(1, "the map uses " + std::to_string(uses.size()) + " messages; the estimator keeps counters for " +
                  std::to_string(fw::kMaxBusMessages));
  map->outputs_ = read_output_ids(r, doc, uses, default_outputs);
  // The DBC's order, as the generated glue numbers them.
  for (const lptn::dbc::Message& m : map->dbc_.messages)
    for (MappedMessage& u : uses)
      if (u.message == &m) map->messages_.push_back(std::move(u));
  return map;
}

fw::BusDecoder BusMap::decoder() const {
  fw::BusDecoder d{&BusMap::decode, this, {}};
  for (const MappedMessage& m : messages_)
    for (const MappedInput& i : m.inputs) d.input_cycle_ms[fw::index_of(i.input)] = m.cycle_ms;
  return d;
}

bool BusMap::decode(const void* self, const fw::CanFrame& f, fw::BusReading& out) {
  const auto& map = *static_cast<const BusMap*>(self);
  for (std::size_t k = 0; k < map.messages_.size(); ++k) {
    const MappedMessage& m = map.messages_[k];
    const lptn::dbc::Message& msg = *m.message;
    if (f.id != msg.id || f.extended != msg.extended) continue;
    out.message = static_cast<int>(k);
    out.carried = m.carried;
    if (f.remote || f.fd != (msg.length > 8) || f.len != msg.length) {
      out.malformed = true;
      return true;
    }
    std::int64_t raw = 0;
    if (m.counter) {
      if (!lptn::dbc::extract_raw(*m.counter, f.data, f.len, raw)) {
        out.malformed = true;
        return true;
      }
      out.has_counter = true;
      out.counter = static_cast<std::uint8_t>(raw);
      out.counter_modulo = static_cast<std::uint16_t>(1u << m.counter->length);
      out.max_delta_counter = static_cast<std::uint8_t>(m.max_delta_counter);
    }
    if (m.crc) {
      if (!lptn::dbc::extract_raw(*m.crc, f.data, f.len, raw)) {
        out.malformed = true;
        return true;
      }
      out.has_crc = true;
      out.crc_ok = fw::e2e::frame_crc(m.data_id, f.data, f.len, m.crc_byte) == static_cast<std::uint8_t>(raw);
    }
    for (const MappedInput& i : m.inputs) {
      if (i.signal->mux == lptn::dbc::Signal::Mux::multiplexed && !lptn::dbc::present(msg, *i.signal, f.data, f.len)) continue;
      if (!lptn::dbc::extract_raw(*i.signal, f.data, f.len, raw)) continue;
      double v = lptn::dbc::to_physical(*i.signal, raw);
      if (i.scale != 1.0 || i.offset != 0.0) v = v * i.scale + i.offset;
      out.add(i.input, v);
    }
    return true;
  }
  return false;
}

std::vector<long long> BusMap::pages(const MappedMessage& m) {
  std::vector<long long> out;
  for (const MappedInput& i : m.inputs)
    if (i.signal->mux == lptn::dbc::Signal::Mux::multiplexed &&
        std::find(out.begin(), out.end(), i.signal->mux_value) == out.end())
      out.push_back(i.signal->mux_value);
  std::sort(out.begin(), out.end());
  if (out.empty()) out.push_back(-1);
  return out;
}

fw::CanFrame BusMap::encode(const MappedMessage& m, const double (&values)[fw::kNumInputs], long long mux,
                            std::uint32_t counter) const {
  const lptn::dbc::Message& msg = *m.message;
  fw::CanFrame f;
  f.id = msg.id;
  f.extended = msg.extended;
  f.len = static_cast<std::uint8_t>(msg.length);
  f.fd = msg.length > 8;
  if (const lptn::dbc::Signal* mx = msg.multiplexor(); mx && mux >= 0) lptn::dbc::insert_raw(*mx, mux, f.data, f.len);
  for (const MappedInput& i : m.inputs) {
    if (i.signal->mux == lptn::dbc::Signal::Mux::multiplexed && i.signal->mux_value != mux) continue;
    const double physical = (values[fw::index_of(i.input)] - i.offset) / i.scale;
    lptn::dbc::insert_raw(*i.signal, raw_of(*i.signal, physical), f.data, f.len);
  }
  if (m.counter) lptn::dbc::insert_raw(*m.counter, static_cast<std::int64_t>(counter % (1u << m.counter->length)), f.data, f.len);
  if (m.crc) lptn::dbc::insert_raw(*m.crc, fw::e2e::frame_crc(m.data_id, f.data, f.len, m.crc_byte), f.data, f.len);
  return f;
}

}  // namespace lptn::bus
