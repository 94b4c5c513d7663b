// data.toml: reading, writing, units and ISO-8601 time stamps.

#include "trainer/data/data_map.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>
#include <toml++/toml.h>

#include "hostio/civil_time.hpp"
#include "hostio/sha256.hpp"
#include "hostio/utf8.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/data/did_you_mean.hpp"

namespace lptn::data {
namespace {

std::string one_line(std::string s) {
  std::replace_if(s.begin(), s.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  return s;
}

[[noreturn]] void fail(const std::filesystem::path& file, const toml::source_region& where, std::string_view key,
                       std::string_view reason) {
  std::ostringstream s;
  s << file.string() << ':' << where.begin.line << ": key '" << key << "': " << reason;
  throw DataError(one_line(s.str()));
}

// Each table's keys checked against the ones it may hold.
void refuse_unknown(const toml::table& t, const std::filesystem::path& file, std::string_view prefix,
                    const std::vector<std::string_view>& known) {
  for (const auto& [key, node] : t) {
    if (std::find(known.begin(), known.end(), key.str()) != known.end()) continue;
    const std::string full = prefix.empty() ? std::string(key.str()) : std::string(prefix) + "." + std::string(key.str());
    fail(file, node.source(), full, "unknown key" + did_you_mean(key.str(), known));
  }
}

std::string full_key(std::string_view prefix, std::string_view key) {
  return prefix.empty() ? std::string(key) : std::string(prefix) + "." + std::string(key);
}

std::optional<std::string> text_value(const toml::table& t, std::string_view key, const std::filesystem::path& file,
                                      std::string_view prefix) {
  const toml::node* n = t.get(key);
  if (!n) return std::nullopt;
  const auto v = n->value<std::string>();
  if (!v) fail(file, n->source(), full_key(prefix, key), "must be a string (in quotes)");
  return *v;
}

std::optional<double> number_value(const toml::table& t, std::string_view key, const std::filesystem::path& file,
                                   std::string_view prefix) {
  const toml::node* n = t.get(key);
  if (!n) return std::nullopt;
  const auto v = n->value<double>();
  if (!v || !std::isfinite(*v)) fail(file, n->source(), full_key(prefix, key), "must be a finite number");
  return *v;
}

std::vector<std::string> text_list(const toml::table& t, std::string_view key, const std::filesystem::path& file,
                                   std::string_view prefix) {
  std::vector<std::string> out;
  const toml::node* n = t.get(key);
  if (!n) return out;
  const toml::array* a = n->as_array();
  if (!a) fail(file, n->source(), full_key(prefix, key), "must be a list of strings: [\"a\", \"b\"]");
  for (const toml::node& item : *a) {
    const auto v = item.value<std::string>();
    if (!v) fail(file, item.source(), full_key(prefix, key), "must hold strings only");
    out.push_back(*v);
  }
  return out;
}

const toml::table* table_value(const toml::table& t, std::string_view key, const std::filesystem::path& file) {
  const toml::node* n = t.get(key);
  if (!n) return nullptr;
  if (!n->as_table()) fail(file, n->source(), key, "must be a table ([" + std::string(key) + "])");
  return n->as_table();
}

// One character, named in words in messages.
char single_char(const std::string& s, const toml::node& n, const std::filesystem::path& file, std::string_view key) {
  if (s.size() != 1) fail(file, n.source(), key, "must be one character, such as \",\" \";\" or \"\\t\"");
  const char c = s[0];
  if (c == '\n' || c == '\r' || c == '"') fail(file, n.source(), key, "cannot be a line end or a quote");
  return c;
}

std::string_view format_name(TimeFormat f) {
  switch (f) {
    case TimeFormat::seconds: return "seconds";
    case TimeFormat::milliseconds: return "milliseconds";
    case TimeFormat::iso8601: return "iso8601";
  }
  return "seconds";
}

constexpr std::string_view kTimeFormats[] = {"seconds", "milliseconds", "epoch_seconds", "epoch_milliseconds",
                                             "iso8601"};

// Kinds of channel, for their units.
enum class Quantity { temperature, speed, frequency, flow, current, torque, voltage };

Quantity quantity_of(Channel c) {
  switch (c) {
    case Channel::speed_rpm: return Quantity::speed;
    case Channel::torque_nm: return Quantity::torque;
    case Channel::current_a: return Quantity::current;
    case Channel::frequency_hz: return Quantity::frequency;
    case Channel::voltage_v: return Quantity::voltage;
    case Channel::airflow_m3s: return Quantity::flow;
    case Channel::ambient_c:
    case Channel::stator_winding_c:
    case Channel::rotor_c: return Quantity::temperature;
  }
  return Quantity::temperature;
}

// A TOML basic string: quotes and backslashes escaped, control characters as \uXXXX (TOML allows
// none of them raw but the tab).
std::string quote(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (c == '\t') {
      out += "\\t";
    } else if (u < 0x20 || u == 0x7F) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04X", static_cast<unsigned>(u));
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string number_text(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, r.ptr);
  // TOML wants a float to look like one when it is not an integer; an integer reads as one.
  return s;
}

}  // namespace

std::vector<UnitConversion> units_of(Channel c) {
  constexpr double kRpmPerRadS = 60.0 / (2.0 * std::numbers::pi);
  switch (quantity_of(c)) {
    case Quantity::temperature:
      return {{"°C", 1, 0}, {"degC", 1, 0}, {"C", 1, 0}, {"K", 1, -273.15}, {"°F", 5.0 / 9.0, -32.0 * 5.0 / 9.0},
              {"degF", 5.0 / 9.0, -32.0 * 5.0 / 9.0}, {"F", 5.0 / 9.0, -32.0 * 5.0 / 9.0}};
    case Quantity::speed:
      return {{"rpm", 1, 0}, {"1/min", 1, 0}, {"rad/s", kRpmPerRadS, 0}, {"Hz", 60, 0}, {"rev/s", 60, 0}};
    case Quantity::frequency:
      return {{"Hz", 1, 0}, {"rad/s", 1.0 / (2.0 * std::numbers::pi), 0}, {"kHz", 1000, 0}};
    case Quantity::flow:
      return {{"m³/s", 1, 0}, {"m3/s", 1, 0}, {"l/s", 1e-3, 0}, {"L/s", 1e-3, 0}, {"m³/h", 1.0 / 3600.0, 0},
              {"m3/h", 1.0 / 3600.0, 0}, {"l/min", 1.0 / 60000.0, 0}, {"L/min", 1.0 / 60000.0, 0},
              {"cfm", 0.3048 * 0.3048 * 0.3048 / 60.0, 0}};
    case Quantity::current: return {{"A", 1, 0}, {"kA", 1000, 0}, {"mA", 1e-3, 0}};
    case Quantity::torque: return {{"Nm", 1, 0}, {"N·m", 1, 0}, {"N m", 1, 0}, {"kNm", 1000, 0}, {"kN·m", 1000, 0}};
    case Quantity::voltage: return {{"V", 1, 0}, {"kV", 1000, 0}};
  }
  return {};
}

std::optional<UnitConversion> find_unit(Channel c, std::string_view unit) {
  for (const UnitConversion& u : units_of(c)) {
    if (u.unit == unit) return u;
  }
  return std::nullopt;
}

DataMap parse_data_map(std::string_view text, const std::filesystem::path& file) {
  toml::table root;
  try {
    root = toml::parse(text, file.string());
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << file.string() << ':' << e.source().begin.line << ": " << e.description();
    throw DataError(one_line(s.str()));
  }
  DataMap m;
  m.file = file;
  refuse_unknown(root, file, "", {"csv", "time", "split", "columns", "ignore"});
  m.ignore = text_list(root, "ignore", file, "");

  if (const toml::table* csv = table_value(root, "csv", file)) {
    refuse_unknown(*csv, file, "csv", {"separator", "decimal", "comment", "missing"});
    if (const auto s = text_value(*csv, "separator", file, "csv")) m.separator = single_char(*s, *csv->get("separator"), file, "csv.separator");
    if (const auto s = text_value(*csv, "decimal", file, "csv")) {
      if (*s != "." && *s != ",") fail(file, csv->get("decimal")->source(), "csv.decimal", "must be \".\" or \",\"");
      m.decimal = (*s)[0];
    }
    if (m.decimal == m.separator)
      fail(file, csv->source(), "csv.decimal", "is the separator too; a decimal comma needs separator = \";\"");
    if (const auto s = text_value(*csv, "comment", file, "csv")) m.comment = *s;
    m.missing = text_list(*csv, "missing", file, "csv");
  }

  if (const toml::table* time = table_value(root, "time", file)) {
    refuse_unknown(*time, file, "time", {"column", "format"});
    if (const auto s = text_value(*time, "column", file, "time")) m.time_column = *s;
    if (const auto s = text_value(*time, "format", file, "time")) {
      if (*s == "seconds" || *s == "epoch_seconds") {
        m.time_format = TimeFormat::seconds;
      } else if (*s == "milliseconds" || *s == "epoch_milliseconds") {
        m.time_format = TimeFormat::milliseconds;
      } else if (*s == "iso8601") {
        m.time_format = TimeFormat::iso8601;
      } else {
        fail(file, time->get("format")->source(), "time.format",
             "unknown format '" + *s + "'" + did_you_mean(*s, kTimeFormats) +
                 "; one of seconds, milliseconds, epoch_seconds, epoch_milliseconds, iso8601");
      }
    }
  }

  if (const toml::table* split = table_value(root, "split", file)) {
    refuse_unknown(*split, file, "split", {"pause_s", "column"});
    if (const auto v = number_value(*split, "pause_s", file, "split")) {
      if (!(*v > 0)) fail(file, split->get("pause_s")->source(), "split.pause_s", "must be greater than zero");
      m.split_pause_s = *v;
    }
    if (const auto s = text_value(*split, "column", file, "split")) m.split_column = *s;
  }

  if (const toml::table* columns = table_value(root, "columns", file)) {
    std::vector<std::string_view> names;
    for (Channel c : kAllChannels) names.push_back(channel_name(c));
    refuse_unknown(*columns, file, "columns", names);
    for (Channel c : kAllChannels) {
      const toml::node* n = columns->get(channel_name(c));
      if (!n) continue;
      const std::string key = "columns." + std::string(channel_name(c));
      ColumnSource src;
      if (const auto name = n->value<std::string>()) {
        src.column = *name;  // a name alone: the column is in lptn's unit
      } else if (const toml::table* t = n->as_table()) {
        refuse_unknown(*t, file, key, {"column", "unit", "scale", "offset"});
        const auto column = text_value(*t, "column", file, key);
        if (!column) fail(file, t->source(), key + ".column", "missing (required): the source column's name");
        src.column = *column;
        const auto unit = text_value(*t, "unit", file, key);
        const auto scale = number_value(*t, "scale", file, key);
        const auto offset = number_value(*t, "offset", file, key);
        if (unit && (scale || offset))
          fail(file, t->get("unit")->source(), key + ".unit", "give a unit or a scale and offset, not both");
        if (unit) {
          const auto u = find_unit(c, *unit);
          if (!u) {
            std::string known;
            for (const UnitConversion& k : units_of(c)) known += (known.empty() ? "" : ", ") + std::string(k.unit);
            fail(file, t->get("unit")->source(), key + ".unit",
                 "unknown unit '" + *unit + "' for this channel; one of " + known + " (or scale and offset)");
          }
          src.unit = *unit;
          src.scale = u->scale;
          src.offset = u->offset;
        } else {
          if (scale && !(*scale != 0))
            fail(file, t->get("scale")->source(), key + ".scale", "must not be zero");
          src.scale = scale.value_or(1.0);
          src.offset = offset.value_or(0.0);
        }
      } else {
        fail(file, n->source(), key,
             "must be the column's name (\"T_rotor\") or a table ({ column = \"T_rotor\", unit = \"K\" })");
      }
      if (src.column.empty()) fail(file, n->source(), key, "the column's name is empty");
      m.columns[index_of(c)] = std::move(src);
    }
  }

  // Every source column feeds one thing.
  std::vector<std::pair<std::string_view, std::string>> used{{m.time_column, "time.column"}};
  if (!m.split_column.empty()) used.emplace_back(m.split_column, "split.column");
  for (Channel c : kAllChannels) {
    if (m.columns[index_of(c)]) used.emplace_back(m.columns[index_of(c)]->column, "columns." + std::string(channel_name(c)));
  }
  for (std::size_t i = 0; i < used.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (used[i].first != used[j].first) continue;
      const toml::node* n = root.at_path(used[i].second).node();
      fail(file, n ? n->source() : root.source(), used[i].second,
           "column '" + std::string(used[i].first) + "' is already read as " + used[j].second);
    }
  }
  for (const std::string& ig : m.ignore) {
    for (const auto& [name, key] : used) {
      if (name == ig)
        fail(file, root.get("ignore")->source(), "ignore", "column '" + ig + "' is ignored and read as " + key);
    }
  }
  return m;
}

DataMap load_data_map(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw DataError(file.string() + ": cannot open the data map");
  std::ostringstream s;
  s << in.rdbuf();
  return parse_data_map(s.str(), file);
}

std::string data_map_sha256(const DataMap& map) {
  const std::string text = format_data_map(map);
  return hostio::sha256_hex(text.data(), text.size());
}

std::string format_data_map(const DataMap& m, std::string_view header_comment) {
  std::ostringstream o;
  std::istringstream lines{std::string(header_comment)};
  for (std::string line; std::getline(lines, line);) {
    // A comment is UTF-8 without control characters too; it may quote an export's bytes.
    line = hostio::as_utf8(line);
    for (char& c : line)
      if ((static_cast<unsigned char>(c) < 0x20 && c != '\t') || c == 0x7F) c = '?';
    o << (line.empty() ? "#" : "# " + line) << '\n';
  }
  if (!header_comment.empty()) o << '\n';
  if (!m.ignore.empty()) {
    o << "# Columns lptn does not read, left out without a word.\nignore = [";
    for (std::size_t i = 0; i < m.ignore.size(); ++i) o << (i ? ", " : "") << quote(m.ignore[i]);
    o << "]\n\n";
  }
  o << "[csv]\n";
  o << "separator = " << quote(std::string(1, m.separator)) << '\n';
  o << "decimal = " << quote(std::string(1, m.decimal)) << '\n';
  if (!m.comment.empty()) o << "comment = " << quote(m.comment) << "   # lines starting with this are skipped\n";
  if (!m.missing.empty()) {
    o << "missing = [";
    for (std::size_t i = 0; i < m.missing.size(); ++i) o << (i ? ", " : "") << quote(m.missing[i]);
    o << "]   # cells read as missing, besides empty ones\n";
  }
  o << "\n[time]\ncolumn = " << quote(m.time_column) << "\nformat = " << quote(format_name(m.time_format))
    << "   # seconds, milliseconds (any origin) or iso8601\n";
  if (m.split_pause_s > 0 || !m.split_column.empty()) {
    o << "\n# One file holds several drives: cut it\n[split]\n";
    if (m.split_pause_s > 0) o << "pause_s = " << number_text(m.split_pause_s) << "   # at pauses longer than this\n";
    if (!m.split_column.empty()) o << "column = " << quote(m.split_column) << "   # at every change of this column\n";
  }
  o << "\n# lptn's channel = { column = the export's name, unit = its unit } (or scale and offset:\n"
       "# lptn's value = value * scale + offset). docs/data-map.md lists the units.\n[columns]\n";
  for (Channel c : kAllChannels) {
    const auto& src = m.columns[index_of(c)];
    if (!src) continue;
    o << channel_name(c) << " = { column = " << quote(src->column);
    if (!src->unit.empty()) {
      o << ", unit = " << quote(src->unit);
    } else if (src->scale != 1.0 || src->offset != 0.0) {
      o << ", scale = " << number_text(src->scale) << ", offset = " << number_text(src->offset);
    }
    o << " }\n";
  }
  return o.str();
}

namespace {

bool digits(std::string_view s, std::size_t at, std::size_t n, unsigned& out) {
  if (at + n > s.size()) return false;
  out = 0;
  for (std::size_t i = at; i < at + n; ++i) {
    if (s[i] < '0' || s[i] > '9') return false;
    out = out * 10 + static_cast<unsigned>(s[i] - '0');
  }
  return true;
}

}  // namespace

bool parse_iso8601(std::string_view s, long long& whole_s, std::string_view& fraction) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '"')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '"')) s.remove_suffix(1);
  unsigned year, month, day, hour, minute, second = 0;
  if (!digits(s, 0, 4, year) || s.size() < 16 || s[4] != '-' || !digits(s, 5, 2, month) || s[7] != '-' ||
      !digits(s, 8, 2, day) || (s[10] != 'T' && s[10] != ' ') || !digits(s, 11, 2, hour) || s[13] != ':' ||
      !digits(s, 14, 2, minute))
    return false;
  std::size_t at = 16;
  fraction = {};
  if (at < s.size() && s[at] == ':') {
    if (!digits(s, at + 1, 2, second)) return false;
    at += 3;
    if (at < s.size() && (s[at] == '.' || s[at] == ',')) {
      const std::size_t first = ++at;
      while (at < s.size() && s[at] >= '0' && s[at] <= '9') ++at;
      if (at == first || at - first > 12) return false;
      fraction = s.substr(first, at - first);
    }
  }
  static constexpr unsigned kDays[] = {31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
  if (month < 1 || month > 12 || day < 1 || day > kDays[month - 1] || (month == 2 && day == 29 && !leap) ||
      hour > 23 || minute > 59 || second > 60)
    return false;
  long long zone_s = 0;
  if (at < s.size()) {
    if (s[at] == 'Z' || s[at] == 'z') {
      ++at;
    } else if (s[at] == '+' || s[at] == '-') {
      const int sign = s[at] == '+' ? 1 : -1;
      unsigned zh, zm = 0;
      if (!digits(s, at + 1, 2, zh)) return false;
      at += 3;
      if (at < s.size() && s[at] == ':') ++at;
      if (at < s.size()) {
        if (!digits(s, at, 2, zm)) return false;
        at += 2;
      }
      if (zh > 23 || zm > 59) return false;
      zone_s = sign * static_cast<long long>(zh * 3600 + zm * 60);
    }
    if (at != s.size()) return false;
  }
  whole_s = hostio::days_from_civil(year, month, day) * 86400 + hour * 3600LL + minute * 60LL + second - zone_s;
  return true;
}

bool seconds_with_fraction(long long whole_s, std::string_view fraction, double& seconds) {
  if (whole_s < 0 && !fraction.empty()) {  // -2 and .5 is -1.5, not "-2.5"
    double f = 0;
    if (!seconds_with_fraction(0, fraction, f)) return false;
    seconds = static_cast<double>(whole_s) + f;
    return true;
  }
  char buf[48];
  const int n = std::snprintf(buf, sizeof buf, "%lld.%.*s0", whole_s, static_cast<int>(fraction.size()), fraction.data());
  if (n <= 0 || static_cast<std::size_t>(n) >= sizeof buf) return false;
  return std::from_chars(buf, buf + n, seconds).ec == std::errc();
}

bool parse_iso8601(std::string_view s, double& seconds) {
  long long whole = 0;
  std::string_view fraction;
  return parse_iso8601(s, whole, fraction) && seconds_with_fraction(whole, fraction, seconds);
}

}  // namespace lptn::data
