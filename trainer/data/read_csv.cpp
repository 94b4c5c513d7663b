// CSV text -> per-channel sample lists. One pass over a buffer holding the whole file, no
// allocation per cell: a fleet dump can be hundreds of hours at 10 Hz.

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <iterator>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

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

std::string_view header_name(std::string_view cell) {
  cell = trim(cell);
  if (cell.size() >= 2 && cell.front() == '"' && cell.back() == '"') cell = trim(cell.substr(1, cell.size() - 2));
  return cell;
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

RawCycle parse_csv(std::string_view text, const std::filesystem::path& file) {
  RawCycle raw;
  raw.file = file;
  const std::string where = file.string();

  LineSplitter lines(text);
  std::string_view line;
  bool have_header = false;
  while (lines.next(line)) {
    if (!trim(line).empty()) {
      have_header = true;
      break;
    }
  }
  if (!have_header) fail(file, 1, {}, "empty file; expected a header row naming time_s and the channels");
  const std::size_t header_line = lines.line_number();

  // Column index -> time, channel index, or ignored.
  std::vector<int> slots;
  std::vector<std::string_view> names;
  {
    CellSplitter cells(line);
    std::string_view cell;
    while (cells.next(cell)) {
      const std::string_view name = header_name(cell);
      const std::size_t column = names.size() + 1;
      if (!name.empty() && std::find(names.begin(), names.end(), name) != names.end()) {
        fail(file, header_line, name, strf("duplicate column name (column %zu)", column));
      }
      names.push_back(name);
      if (name == kTimeColumn) {
        slots.push_back(kTimeSlot);
      } else if (const auto c = channel_from_name(name)) {
        slots.push_back(static_cast<int>(index_of(*c)));
        raw.channels[index_of(*c)].present = true;
      } else {
        slots.push_back(kIgnoredSlot);
        raw.findings.push_back(
            {Finding::Severity::warning,
             name.empty() ? strf("%s:%zu: column %zu has no name; ignored", where.c_str(), header_line, column)
                          : strf("%s:%zu: column '%.*s': unknown column; ignored%s", where.c_str(), header_line,
                                 static_cast<int>(name.size()), name.data(), column_suggestion(name).c_str())});
      }
    }
  }

  const auto missing = [&](std::string_view required) {
    std::string reason = "required column missing";
    for (std::string_view n : names) {
      if (iequals(n, required)) {
        reason += " (there is '" + std::string(n) + "'; names are case-sensitive)";
        break;
      }
    }
    fail(file, header_line, required, reason);
  };
  if (std::find(slots.begin(), slots.end(), kTimeSlot) == slots.end()) missing(kTimeColumn);
  for (Channel c : kAllChannels) {
    if (channel_info(c).required && !raw.channels[index_of(c)].present) missing(channel_name(c));
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

  while (lines.next(line)) {
    if (trim(line).empty()) continue;  // a stray blank line (typically the last) carries nothing
    const std::size_t n = lines.line_number();
    if (const std::size_t cells = count_cells(line); cells != columns) {
      fail(file, n, {}, strf("row has %zu cells, the header has %zu", cells, columns));
    }
    if (raw.time.size() >= std::numeric_limits<std::uint32_t>::max() ||
        n > std::numeric_limits<std::uint32_t>::max()) {
      fail(file, n, {}, "too many rows for one cycle file");
    }
    const auto row = static_cast<std::uint32_t>(raw.time.size());
    double t = 0;
    CellSplitter cells(line);
    std::string_view cell;
    for (std::size_t col = 0; cells.next(cell); ++col) {
      const int slot = slots[col];
      if (slot == kIgnoredSlot) continue;
      const std::string_view name =
          slot == kTimeSlot ? kTimeColumn : channel_name(kAllChannels[static_cast<std::size_t>(slot)]);
      double v = 0;
      switch (parse_number(cell, v)) {
        case NumberStatus::empty:
          if (slot == kTimeSlot) fail(file, n, name, "time missing; every row needs one");
          continue;
        case NumberStatus::not_a_number:
          fail(file, n, name, "not a number: " + quoted(cell));
        case NumberStatus::non_finite:
          fail(file, n, name, "NaN or infinity is not a measurement (leave the cell empty): " + quoted(cell));
        case NumberStatus::out_of_range:
          fail(file, n, name, "number out of range: " + quoted(cell));
        case NumberStatus::ok:
          break;
      }
      if (slot == kTimeSlot) {
        if (!raw.time.empty() && v < raw.time.back()) {
          fail(file, n, name,
               strf("time goes backwards: %s s after %s s on line %u", num(v).c_str(),
                    num(raw.time.back()).c_str(), static_cast<unsigned>(raw.line.back())));
        }
        t = v;
      } else {
        const ChannelInfo& info = kChannelTable[static_cast<std::size_t>(slot)];
        if (v < info.min || v > info.max) {
          std::string reason = strf("%s %.*s is outside the physically possible %s..%s", quoted(cell).c_str(),
                                    static_cast<int>(info.unit.size()), info.unit.data(), num(info.min).c_str(),
                                    num(info.max).c_str());
          if (!is_sensor_channel(static_cast<std::size_t>(slot))) fail(file, n, name, reason);
          if (deferred.line == 0) deferred = {n, name, std::move(reason)};
        }
        RawChannel& ch = raw.channels[static_cast<std::size_t>(slot)];
        ch.rows.push_back(row);
        ch.values.push_back(v);
      }
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
        fail(file, header_line, channel_name(c),
             strf("kelvin? this column reads %.0f while ambient_c reads %.0f (medians over the file; the contract "
                  "is degrees Celsius)",
                  sensor_median, ambient_median));
      }
    }
  }
  if (deferred.line != 0) fail(file, deferred.line, deferred.column, deferred.reason);
  for (Channel c : kAllChannels) {
    const RawChannel& ch = raw.channels[index_of(c)];
    if (!ch.present || !ch.values.empty()) continue;
    if (channel_info(c).required) {
      fail(file, header_line, channel_name(c),
           strf("required channel has no value in any of the %zu data rows", raw.time.size()));
    }
    raw.findings.push_back({Finding::Severity::info,
                            strf("%s: column '%.*s': present but empty (optional)", where.c_str(),
                                 static_cast<int>(channel_name(c).size()), channel_name(c).data())});
  }
  return raw;
}

}  // namespace lptn::data::internal
