// CSV text -> per-channel sample lists. One pass over a buffer holding the whole file, no
// allocation per cell: a fleet dump can be hundreds of hours at 10 Hz.

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <iterator>
#include <cstdint>
#include <deque>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "hostio/utf8.hpp"
#include "trainer/data/data_map.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/data/did_you_mean.hpp"
#include "trainer/data/internal/csv.hpp"
#include "trainer/data/internal/raw_cycle.hpp"
#include "trainer/data/internal/text.hpp"

namespace lptn::data::internal {
namespace {

[[noreturn]] void fail(const std::filesystem::path& file, std::size_t line, std::string_view column,
                       const std::string& reason) {
  std::string msg = file.string() + ":" + std::to_string(line) + ": ";
  if (!column.empty()) msg += "column '" + std::string(column) + "': ";
  msg += reason;
  // The contract is one line per error; a path or cell should never break it.
  std::replace_if(msg.begin(), msg.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  throw DataError(msg);
}

// A cell for quoting in a message: bounded, so a runaway line does not become the message.
std::string quoted(std::string_view cell) {
  cell = trim(cell);
  constexpr std::size_t kMax = 40;
  // Appended piecewise: GCC 12 warns falsely (-Wrestrict) on "'" + std::string(...) at -O3.
  std::string out;
  out.reserve(kMax + 5);
  out += '\'';
  out.append(cell.substr(0, kMax));
  if (cell.size() > kMax) out += "...";
  out += '\'';
  return out;
}

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

constexpr int kTimeSlot = -2;
constexpr int kIgnoredSlot = -1;

// A temperature sensor logged in kelvin reads 273 K plus the motor's rise above the air. The
// hottest insulation classes (200 and 220 degC at the hot spot) over 40 degC of air allow at most
// 180 K of rise at the hottest point, and most of a cycle lies well below its peak; a column that
// lies this far above the ambient's median for three quarters of its readings reads kelvin, not a
// motor hotter than any insulation.
constexpr double kKelvinRiseK = 230.0;

// The channels compared with ambient_c for kelvin; ambient_c itself is beyond its own range in kelvin.
constexpr Channel kSensorChannels[] = {Channel::stator_winding_c, Channel::rotor_c};

bool is_sensor_channel(std::size_t slot) {
  return std::any_of(std::begin(kSensorChannels), std::end(kSensorChannels),
                     [&](Channel c) { return index_of(c) == slot; });
}

// " (did you mean 'rotor_c'?)" for a column name that is a typo of the contract's.
std::string column_suggestion(std::string_view name) {
  std::vector<std::string_view> known{kTimeColumn};
  for (Channel c : kAllChannels) known.push_back(channel_name(c));
  return did_you_mean(name, known);
}

// The value below which `share` of the values lie (a copy is partly sorted): robust to spikes.
double quantile(std::vector<double> v, double share) {
  const auto at = v.begin() + static_cast<std::ptrdiff_t>(share * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), at, v.end());
  return *at;
}

// The first out-of-range reading of a sensor column, held back until the whole column has been seen:
// a column in kelvin is better told as that than as its first reading above 400 degC.
struct DeferredRangeError {
  std::size_t line = 0;
  std::string_view column;
  std::string reason;
};

}  // namespace

namespace {

constexpr int kSplitSlot = -3;

struct Slot {
  int kind = kIgnoredSlot;  // a channel's index, or one of the k*Slot values
  double scale = 1.0, offset = 0.0;
  bool convert = false;  // scale or offset differ from identity (else the value is taken as read)
};

// Characters a cycle name keeps: a shell takes it as one word without quotes.
std::string shell_safe(std::string_view s) {
  std::string out;
  for (char c : s) {
    const bool keep = std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-' || c == '+';
    out += keep ? c : '_';
  }
  return out.empty() ? std::string("_") : out;
}

std::string list_names(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? ", '" : "'") + names[i] + "'";
  return out;
}

const DataMap& default_map() {
  static const DataMap m;
  return m;
}

// The pieces a map's [split] cuts one file's rows into: [begin, end) rows, each with its name.
struct Piece {
  std::size_t begin, end;
  std::string name;
};

RawCycle slice(const RawCycle& raw, const Piece& p) {
  RawCycle out;
  out.file = raw.file;
  out.name = p.name;
  out.time.assign(raw.time.begin() + static_cast<std::ptrdiff_t>(p.begin), raw.time.begin() + static_cast<std::ptrdiff_t>(p.end));
  out.line.assign(raw.line.begin() + static_cast<std::ptrdiff_t>(p.begin), raw.line.begin() + static_cast<std::ptrdiff_t>(p.end));
  for (std::size_t c = 0; c < raw.channels.size(); ++c) {
    const RawChannel& from = raw.channels[c];
    RawChannel& to = out.channels[c];
    to.present = from.present;
    const auto lo = std::lower_bound(from.rows.begin(), from.rows.end(), static_cast<std::uint32_t>(p.begin));
    const auto hi = std::lower_bound(lo, from.rows.end(), static_cast<std::uint32_t>(p.end));
    for (auto it = lo; it != hi; ++it) {
      to.rows.push_back(*it - static_cast<std::uint32_t>(p.begin));
      to.values.push_back(from.values[static_cast<std::size_t>(it - from.rows.begin())]);
    }
  }
  return out;
}

}  // namespace

std::vector<RawCycle> parse_csv(std::string_view text, const std::filesystem::path& file, const DataMap* map_or_null) {
  const DataMap& map = map_or_null ? *map_or_null : default_map();
  const bool mapped = map_or_null != nullptr;
  const char sep = map.separator;
  const std::string via = mapped && !map.file.empty() ? " (data map " + map.file.string() + ")" : std::string();
  RawCycle raw;
  raw.file = file;
  raw.name = file.stem().string();
  const std::string where = file.string();

  LineSplitter lines(text);
  std::string_view line;
  bool have_header = false;
  while (lines.next(line)) {
    if (!trim(line).empty() && !is_comment(line, map.comment)) {
      have_header = true;
      break;
    }
  }
  if (!have_header)
    fail(file, 1, {}, strf("empty file; expected a header row naming %s and the channels", map.time_column.c_str()));
  const std::size_t header_line = lines.line_number();

  // Column index -> time, channel (with its unit's conversion), the split column, or ignored.
  std::vector<Slot> slots;
  std::vector<std::string_view> names;
  // As UTF-8 (Windows-1252 headers read as Latin-1: a map, TOML, spells their "°C" in UTF-8); a
  // deque keeps the views valid.
  std::deque<std::string> owned_names;
  std::vector<std::string> unknown, unknown_hint;  // named in one finding; "did you mean" for each
  {
    CellSplitter cells(line, sep);
    std::string_view cell;
    while (cells.next(cell)) {
      const std::string_view name = owned_names.emplace_back(hostio::as_utf8(unquoted(cell)));
      const std::size_t column = names.size() + 1;
      if (!name.empty() && std::find(names.begin(), names.end(), name) != names.end()) {
        fail(file, header_line, name, strf("duplicate column name (column %zu)", column));
      }
      names.push_back(name);
      Slot slot;
      if (name == map.time_column) {
        slot.kind = kTimeSlot;
      } else if (!map.split_column.empty() && name == map.split_column) {
        slot.kind = kSplitSlot;
      } else if (const auto c = std::find_if(kAllChannels.begin(), kAllChannels.end(),
                                             [&](Channel ch) { return map.source_of(ch) == name; });
                 c != kAllChannels.end()) {
        slot.kind = static_cast<int>(index_of(*c));
        raw.channels[index_of(*c)].present = true;
        if (const auto& src = map.columns[index_of(*c)]) {
          slot.scale = src->scale;
          slot.offset = src->offset;
          slot.convert = src->scale != 1.0 || src->offset != 0.0;
        }
      } else if (std::find(map.ignore.begin(), map.ignore.end(), name) == map.ignore.end()) {
        unknown.push_back(name.empty() ? strf("column %zu has no name", column) : "'" + std::string(name) + "'");
        unknown_hint.push_back(name.empty() || mapped ? std::string() : column_suggestion(name));
      }
      slots.push_back(slot);
    }
  }
  if (!unknown.empty()) {
    std::string list;
    for (std::size_t i = 0; i < unknown.size(); ++i) list += (i ? ", " : "") + unknown[i] + unknown_hint[i];
    raw.findings.push_back(
        {Finding::Severity::warning,
         unknown.size() == 1 && names.size() > 1
             ? strf("%s:%zu: column %s: unknown column; ignored%s%s", where.c_str(), header_line, unknown[0].c_str(),
                    unknown_hint[0].c_str(), via.c_str())
             : strf("%s:%zu: columns %s: unknown columns; ignored%s (a data map's ignore = [...] leaves them out "
                    "without a word)",
                    where.c_str(), header_line, list.c_str(), via.c_str())});
  }

  // Every missing column at once, each by the name the header should have had.
  std::vector<std::string> missing;
  std::string case_hint;
  const auto check_present = [&](std::string_view source, std::string_view channel) {
    missing.push_back(source != channel ? std::string(source) + "' (" + std::string(channel) + ")"
                                        : std::string(source));
    for (std::string_view n : names) {
      if (case_hint.empty() && iequals(n, source))
        case_hint = " (there is '" + std::string(n) + "'; names are case-sensitive)";
    }
  };
  if (std::none_of(slots.begin(), slots.end(), [](const Slot& s) { return s.kind == kTimeSlot; }))
    check_present(map.time_column, kTimeColumn);
  if (!map.split_column.empty() &&
      std::none_of(slots.begin(), slots.end(), [](const Slot& s) { return s.kind == kSplitSlot; }))
    check_present(map.split_column, "split.column");
  for (Channel c : kAllChannels) {
    if (channel_info(c).required && !raw.channels[index_of(c)].present) check_present(map.source_of(c), channel_name(c));
  }
  // Optional channels the map names must be there too: a misspelt rotor column is no absent rotor.
  for (Channel c : kAllChannels) {
    if (!channel_info(c).required && map.columns[index_of(c)] && !raw.channels[index_of(c)].present)
      check_present(map.source_of(c), channel_name(c));
  }
  if (!missing.empty()) {
    std::string column = missing.front();
    for (std::size_t i = 1; i < missing.size(); ++i) column += "', '" + missing[i];
    std::string reason = missing.size() == 1 ? "required column missing" : "required columns missing";
    reason += case_hint;
    if (names.size() == 1 && sep == ',') {
      for (const char other : {';', '\t', '|'}) {
        if (line.find(other) != std::string_view::npos) {
          reason += strf("; the header is separated by '%s', not ',': a data map's [csv] separator = \"%s\" reads it",
                         other == '\t' ? "\\t" : std::string(1, other).c_str(),
                         other == '\t' ? "\\t" : std::string(1, other).c_str());
          break;
        }
      }
    }
    if (map.comment.empty()) {
      for (const std::string_view prefix : {"#", "//", ";"}) {
        if (trim(line).substr(0, prefix.size()) == prefix) {
          reason += strf("; line %zu starts with '%.*s': a data map's [csv] comment = \"%.*s\" skips such lines",
                         header_line, static_cast<int>(prefix.size()), prefix.data(), static_cast<int>(prefix.size()),
                         prefix.data());
          break;
        }
      }
    }
    if (!unknown.empty()) reason += "; the header has " + list_names([&] {
      std::vector<std::string> u;
      for (std::string_view n : names) {
        if (!n.empty()) u.emplace_back(n);
      }
      return u;
    }());
    reason += mapped ? via : "; lptn inspect --suggest-map proposes a data map for an export's own names and units";
    if (missing.size() == 1) fail(file, header_line, column, reason);
    fail(file, header_line, {}, "columns '" + column + "': " + reason);
  }
  for (Channel c : kAllChannels) {
    if (!channel_info(c).required && !raw.channels[index_of(c)].present) {
      raw.findings.push_back({Finding::Severity::info,
                              strf("%s: column '%.*s': absent (optional)", where.c_str(),
                                   static_cast<int>(channel_name(c).size()), channel_name(c).data())});
    }
  }

  DeferredRangeError deferred;
  const std::size_t columns = slots.size();
  const std::size_t expected_rows =
      static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
  raw.time.reserve(expected_rows);
  raw.line.reserve(expected_rows);
  std::vector<Piece> pieces;
  std::string_view split_value;  // the split column's value in the previous row
  long long iso_origin_s = 0;     // ISO-8601 times are read as seconds after this one (the first row's)

  while (lines.next(line)) {
    if (trim(line).empty() || is_comment(line, map.comment)) continue;  // a stray blank line carries nothing
    const std::size_t n = lines.line_number();
    if (const std::size_t cells = count_cells(line, sep); cells != columns) {
      fail(file, n, {}, strf("row has %zu cells, the header has %zu", cells, columns));
    }
    if (raw.time.size() >= std::numeric_limits<std::uint32_t>::max() ||
        n > std::numeric_limits<std::uint32_t>::max()) {
      fail(file, n, {}, "too many rows for one cycle file");
    }
    const auto row = static_cast<std::uint32_t>(raw.time.size());
    double t = 0;
    CellSplitter cells(line, sep);
    std::string_view cell;
    for (std::size_t col = 0; cells.next(cell); ++col) {
      const Slot& slot = slots[col];
      if (slot.kind == kIgnoredSlot) continue;
      if (mapped) {
        cell = unquoted(cell);
        if (std::find(map.missing.begin(), map.missing.end(), cell) != map.missing.end()) cell = {};
      }
      const std::string_view name = slot.kind == kTimeSlot    ? std::string_view(map.time_column)
                                    : slot.kind == kSplitSlot ? std::string_view(map.split_column)
                                                              : map.source_of(kAllChannels[static_cast<std::size_t>(slot.kind)]);
      if (slot.kind == kSplitSlot) {
        const std::string_view value = trim(cell);
        if (row == 0) {
          pieces.push_back({0, 0, std::string(value)});
        } else if (value != split_value) {
          pieces.push_back({row, 0, std::string(value)});
        }
        split_value = value;
        continue;
      }
      double v = 0;
      NumberStatus status;
      if (slot.kind == kTimeSlot && map.time_format == TimeFormat::iso8601) {
        status = trim(cell).empty() ? NumberStatus::empty : NumberStatus::ok;
        long long whole = 0;
        std::string_view fraction;
        if (status == NumberStatus::ok && !parse_iso8601(cell, whole, fraction))
          fail(file, n, name, "not a date-time (YYYY-MM-DDThh:mm:ss[.fff], then Z, +hh:mm or nothing): " + quoted(cell));
        // Seconds after the first row's whole second: epoch-sized times would cost the grid its digits.
        if (status == NumberStatus::ok) {
          if (raw.time.empty()) iso_origin_s = whole;
          if (!seconds_with_fraction(whole - iso_origin_s, fraction, v))
            fail(file, n, name, "date-time out of range: " + quoted(cell));
        }
      } else {
        status = parse_number(cell, map.decimal, v);
      }
      switch (status) {
        case NumberStatus::empty:
          if (slot.kind == kTimeSlot) fail(file, n, name, "time missing; every row needs one");
          continue;
        case NumberStatus::not_a_number: {
          std::string reason = "not a number: " + quoted(cell);
          double ignored = 0;
          if (slot.kind == kTimeSlot && parse_iso8601(cell, ignored)) {
            reason += " (a date-time: a data map's [time] format = \"iso8601\" reads it)";
          } else if (map.decimal == '.' && parse_number(cell, ',', ignored) == NumberStatus::ok) {
            reason += " (a decimal comma: a data map's [csv] decimal = \",\" reads it)";
          }
          fail(file, n, name, reason + via);
        }
        case NumberStatus::non_finite:
          fail(file, n, name,
               "NaN or infinity is not a measurement: " + quoted(cell) +
                   " (leave the cell empty, or list the text under a data map's [csv] missing)" + via);
        case NumberStatus::out_of_range:
          fail(file, n, name, "number out of range: " + quoted(cell));
        case NumberStatus::ok:
          break;
      }
      if (slot.kind == kTimeSlot) {
        if (map.time_format == TimeFormat::milliseconds) v /= 1000.0;
        if (!raw.time.empty() && v < raw.time.back()) {
          fail(file, n, name,
               strf("time goes backwards: %s s after %s s on line %u", num(v).c_str(),
                    num(raw.time.back()).c_str(), static_cast<unsigned>(raw.line.back())));
        }
        t = v;
      } else {
        if (slot.convert) v = v * slot.scale + slot.offset;
        const ChannelInfo& info = kChannelTable[static_cast<std::size_t>(slot.kind)];
        if (v < info.min || v > info.max) {
          std::string reason = strf("%s %.*s is outside the physically possible %s..%s", quoted(cell).c_str(),
                                    static_cast<int>(info.unit.size()), info.unit.data(), num(info.min).c_str(),
                                    num(info.max).c_str());
          if (slot.convert) reason = strf("%s (%s %.*s after the map's unit)", quoted(cell).c_str(), num(v).c_str(),
                                          static_cast<int>(info.unit.size()), info.unit.data()) +
                                     strf(" is outside the physically possible %s..%s", num(info.min).c_str(),
                                          num(info.max).c_str()) + via;
          if (!is_sensor_channel(static_cast<std::size_t>(slot.kind))) fail(file, n, name, reason);
          if (deferred.line == 0) deferred = {n, name, std::move(reason)};
        }
        RawChannel& ch = raw.channels[static_cast<std::size_t>(slot.kind)];
        ch.rows.push_back(row);
        ch.values.push_back(v);
      }
    }
    if (map.split_pause_s > 0 && !raw.time.empty() && t - raw.time.back() > map.split_pause_s &&
        (pieces.empty() || pieces.back().begin != row)) {
      pieces.push_back({row, 0, std::string()});
    }
    raw.time.push_back(t);
    raw.line.push_back(static_cast<std::uint32_t>(n));
  }

  if (raw.time.empty()) fail(file, header_line, {}, "header but no data rows");
  const RawChannel& ambient = raw.channels[index_of(Channel::ambient_c)];
  if (!ambient.values.empty()) {
    const double ambient_median = quantile(ambient.values, 0.5);
    for (Channel c : kSensorChannels) {
      const RawChannel& ch = raw.channels[index_of(c)];
      if (ch.values.empty()) continue;
      // Decided on the lower quartile: a column in kelvin is shifted whole, while a real motor that
      // runs hot spends a part of the file cooler (and a few readings above 400 degC stay what they are).
      if (quantile(ch.values, 0.25) - ambient_median > kKelvinRiseK) {
        const double sensor_median = quantile(ch.values, 0.5);
        fail(file, header_line, map.source_of(c),
             strf("kelvin? this column reads %.0f while %s reads %.0f (medians over the file; the contract "
                  "is degrees Celsius: a data map's unit = \"K\" converts it)%s",
                  sensor_median, std::string(map.source_of(Channel::ambient_c)).c_str(), ambient_median, via.c_str()));
      }
    }
  }
  if (deferred.line != 0) fail(file, deferred.line, deferred.column, deferred.reason);
  for (Channel c : kAllChannels) {
    const RawChannel& ch = raw.channels[index_of(c)];
    if (!ch.present || !ch.values.empty()) continue;
    if (channel_info(c).required) {
      fail(file, header_line, map.source_of(c),
           strf("required channel has no value in any of the %zu data rows", raw.time.size()));
    }
    raw.findings.push_back({Finding::Severity::info,
                            strf("%s: column '%.*s': present but empty (optional)", where.c_str(),
                                 static_cast<int>(channel_name(c).size()), channel_name(c).data())});
  }

  std::vector<RawCycle> out;
  if (pieces.size() <= 1 && map.split_column.empty()) {
    out.push_back(std::move(raw));
    return out;
  }
  // Cut into drives: named by the split column's value, or numbered, in a shell-safe form.
  if (pieces.empty() || pieces.front().begin != 0) pieces.insert(pieces.begin(), Piece{0, 0, std::string()});
  for (std::size_t i = 0; i < pieces.size(); ++i) pieces[i].end = i + 1 < pieces.size() ? pieces[i + 1].begin : raw.time.size();
  std::string label;  // the split column's value carries over pause cuts within one trip
  const int width = static_cast<int>(std::to_string(pieces.size()).size());
  std::vector<std::string> taken;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    Piece& p = pieces[i];
    if (!map.split_column.empty()) {
      if (!p.name.empty() || i == 0) label = p.name;
      p.name = raw.name + "-" + shell_safe(label);
    } else {
      p.name = raw.name + "-" + strf("%0*zu", width, i + 1);
    }
    std::string name = p.name;
    for (int k = 2; std::find(taken.begin(), taken.end(), name) != taken.end(); ++k) name = p.name + "-" + std::to_string(k);
    p.name = name;
    taken.push_back(name);
  }
  for (const Piece& p : pieces) out.push_back(slice(raw, p));
  out.front().findings = std::move(raw.findings);
  out.front().findings.push_back(
      {Finding::Severity::info,
       strf("%s: cut into %zu drives by the data map's [split]: %s ... %s", where.c_str(), pieces.size(),
            pieces.front().name.c_str(), pieces.back().name.c_str())});
  return out;
}

}  // namespace lptn::data::internal
