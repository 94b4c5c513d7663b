#pragma once
// A data map (data.toml): how to read a logger's or data lake's CSV export as lptn's channels.
// Which source column is which channel and in what unit, how time is written, the CSV dialect
// (separator, decimal mark, comment lines, missing-value tokens), how one long file is cut into
// drives and which columns to leave out. docs/data-map.md documents every key with examples.

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "trainer/data/channels.hpp"

namespace lptn::data {

// The name a data map has beside the CSV files it describes (every command that reads a dump
// reads it from there by itself, unless --map names another).
inline constexpr std::string_view kDataMapFileName = "data.toml";

enum class TimeFormat {
  seconds,       // any origin: from the cycle's start, or epoch seconds
  milliseconds,  // any origin
  iso8601,       // 2024-03-04T06:00:00.000Z, a space for the T, with or without a zone
};

struct ColumnSource {
  std::string column;  // the source column's name in the header
  std::string unit;    // as written in the map ("K", "l/s"); empty when scale/offset were given
  // lptn's value = source value * scale + offset.
  double scale = 1.0, offset = 0.0;
};

struct DataMap {
  std::filesystem::path file;  // where it was read from (messages name it); empty when built in code

  char separator = ',';
  char decimal = '.';
  std::string comment;  // a line starting with this (after blanks) is skipped; empty: none
  std::vector<std::string> missing;  // cell texts read as missing (the empty cell always is)

  std::string time_column{kTimeColumn};
  TimeFormat time_format = TimeFormat::seconds;

  // Per channel; an unmapped channel is read from the column of lptn's own name, if any.
  std::array<std::optional<ColumnSource>, kNumChannels> columns;
  std::vector<std::string> ignore;  // source columns left out without a word

  // How one long file is cut into drives (both may be given; each cuts).
  double split_pause_s = 0;  // at pauses in time longer than this; 0: never
  std::string split_column;  // at every change of this column's value; empty: never

  // The source column channel c is read from.
  std::string_view source_of(Channel c) const {
    const auto& m = columns[index_of(c)];
    return m ? std::string_view(m->column) : channel_name(c);
  }
};

// Throws DataError ("FILE:LINE: key 'columns.rotor_c.unit': reason", one line) for a map with an
// error: TOML syntax, an unknown key or unit, a value of the wrong kind, two channels from one column.
DataMap load_data_map(const std::filesystem::path& file);
DataMap parse_data_map(std::string_view text, const std::filesystem::path& shown_as);

// The map as data.toml text, commented; parse_data_map reads it back to an equal map.
// `header_comment` (lines without '#') goes on top.
std::string format_data_map(const DataMap& map, std::string_view header_comment = {});

// What the map reads a file as, as one SHA-256: of its format_data_map() text, so that two maps that
// read alike (comments, key order and layout aside) have the same. A calibration records it for
// each file, and a later reading of the same file through another map is not the data it saw.
std::string data_map_sha256(const DataMap& map);

// The units a channel's column may be given in, and what each converts by (scale, offset).
struct UnitConversion {
  std::string_view unit;
  double scale, offset;
};
std::vector<UnitConversion> units_of(Channel c);
std::optional<UnitConversion> find_unit(Channel c, std::string_view unit);

// Seconds since 1970-01-01T00:00:00 (UTC when the text has a zone; as written when it has none).
// Accepts YYYY-MM-DD, then 'T' or ' ', then hh:mm[:ss[.fraction]], then nothing, 'Z', ±hh, ±hhmm
// or ±hh:mm. False for anything else, a day that does not exist among them.
bool parse_iso8601(std::string_view text, double& seconds);
// The same in parts: whole seconds, and the fraction's digits as written (for exact differences).
bool parse_iso8601(std::string_view text, long long& whole_s, std::string_view& fraction);
// whole_s + 0.fraction as the nearest double, as if "whole_s.fraction" had been written.
bool seconds_with_fraction(long long whole_s, std::string_view fraction, double& seconds);

}  // namespace lptn::data
