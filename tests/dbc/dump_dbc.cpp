// Prints what can/dbc reads from a DBC file, for check_reader.py to hold against
// can/codecs/dbc_codegen.py: one JSON object, {"error": "LINE: reason"} or the frames, and with
// --frames N the raw and physical value of every signal each message carries in N pseudo-random
// payloads (a fixed xorshift sequence both sides draw alike).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "can/dbc/dbc.hpp"

namespace {

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned char>(c));
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::uint64_t next(std::uint64_t& state) {
  state ^= state << 13;
  state ^= state >> 7;
  state ^= state << 17;
  return state;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: dump_dbc FILE [--frames N]\n");
    return 2;
  }
  const int frames = argc >= 4 ? std::atoi(argv[3]) : 0;
  lptn::dbc::Database db;
  try {
    db = lptn::dbc::read(argv[1]);
  } catch (const lptn::dbc::Error& e) {
    const std::string what = e.what();
    const std::string prefix = std::string(argv[1]) + ":";
    std::printf("{\"error\": %s}\n", quoted(what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what).c_str());
    return 0;
  }
  std::printf("{\"messages\": [\n");
  for (std::size_t mi = 0; mi < db.messages.size(); ++mi) {
    const lptn::dbc::Message& m = db.messages[mi];
    std::printf("{\"name\": %s, \"id\": %u, \"extended\": %s, \"length\": %d, \"line\": %d, \"cycle_ms\": %u, \"signals\": [",
                quoted(m.name).c_str(), m.id, m.extended ? "true" : "false", m.length, m.line, m.cycle_ms);
    for (std::size_t si = 0; si < m.signals.size(); ++si) {
      const lptn::dbc::Signal& s = m.signals[si];
      std::string ranges;
      for (const auto& [low, high] : s.mux_ranges)
        ranges += (ranges.empty() ? "" : ", ") + std::string("[") + std::to_string(low) + ", " + std::to_string(high) + "]";
      std::printf("%s{\"name\": %s, \"start\": %d, \"length\": %d, \"big_endian\": %s, \"signed\": %s, \"factor\": %s, "
                  "\"offset\": %s, \"unit\": %s, \"multiplexor\": %s, \"mux_ranges\": %s}",
                  si ? ", " : "", quoted(s.name).c_str(), s.start, s.length, s.big_endian ? "true" : "false",
                  s.is_signed ? "true" : "false", number(s.factor).c_str(), number(s.offset).c_str(), quoted(s.unit).c_str(),
                  s.mux == lptn::dbc::Signal::Mux::multiplexor ? "true" : "false",
                  s.mux == lptn::dbc::Signal::Mux::multiplexed ? ("[" + ranges + "]").c_str() : "null");
    }
    std::printf("], \"frames\": [");
    std::uint64_t state = 0x9E3779B97F4A7C15ull ^ m.id;
    for (int f = 0; f < frames; ++f) {
      std::uint8_t data[64];
      for (int b = 0; b < m.length; ++b) data[b] = static_cast<std::uint8_t>(next(state) >> 56);
      std::printf("%s{", f ? ", " : "");
      bool first = true;
      for (const lptn::dbc::Signal& s : m.signals) {
        std::int64_t raw = 0;
        if (!lptn::dbc::present(m, s, data, m.length) || !lptn::dbc::extract_raw(s, data, m.length, raw)) continue;
        // Encoding the physical value must give the raw value back (the bits hold it exactly).
        const double physical = lptn::dbc::to_physical(s, raw);
        std::uint8_t again[64] = {};
        lptn::dbc::insert_raw(s, raw, again, m.length);
        std::int64_t back = 0;
        lptn::dbc::extract_raw(s, again, m.length, back);
        std::printf("%s%s: [%s, %s, %s]", first ? "" : ", ", quoted(s.name).c_str(),
                    (!s.is_signed && s.length == 64) ? std::to_string(static_cast<std::uint64_t>(raw)).c_str()
                                                     : std::to_string(raw).c_str(),
                    number(physical).c_str(), back == raw ? "true" : "false");
        first = false;
      }
      std::printf("}");
    }
    std::printf("]}%s\n", mi + 1 < db.messages.size() ? "," : "");
  }
  std::printf("]}\n");
  return 0;
}
