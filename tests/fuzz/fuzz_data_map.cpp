// Fuzz target: the data map (trainer/data/data_map.hpp) and a CSV read through it. Input: the
// map's TOML text, then a line "%%\n", then the CSV's text (no such line: the map alone).
//
// Bad input must come out as DataError, one line ("FILE:LINE: key 'KEY': reason" for the map,
// "FILE:LINE: ..." for the CSV); anything else escaping is a finding. A map that parses must
// read back equal from the text format_data_map writes for it (what --suggest-map prints), and a
// CSV that loads through it must be a consistent dataset within the channels' physical ranges.
// What --suggest-map proposes for the CSV must be a map that reads back equal.
#include <cmath>
#include <cstdio>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "fuzz_check.hpp"
#include "trainer/data/data_map.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/data/suggest_map.hpp"

namespace {

using namespace lptn::data;

bool one_line(std::string_view s) { return s.find_first_of("\r\n") == std::string_view::npos; }

bool same(const DataMap& a, const DataMap& b) {
  if (a.separator != b.separator || a.decimal != b.decimal || a.comment != b.comment || a.missing != b.missing ||
      a.time_column != b.time_column || a.time_format != b.time_format || a.ignore != b.ignore ||
      a.split_pause_s != b.split_pause_s || a.split_column != b.split_column)
    return false;
  for (std::size_t i = 0; i < a.columns.size(); ++i) {
    const auto &x = a.columns[i], &y = b.columns[i];
    if (x.has_value() != y.has_value()) return false;
    if (x && (x->column != y->column || x->scale != y->scale || x->offset != y->offset)) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const std::size_t cut = input.find("%%\n");
  const std::string_view map_text = input.substr(0, cut);
  DataMap map;
  try {
    map = parse_data_map(map_text, "fuzz.toml");
  } catch (const DataError& e) {
    LPTN_FUZZ_CHECK(one_line(e.what()), "a map error of more than one line");
    return 0;
  }
  try {
    LPTN_FUZZ_CHECK(same(map, parse_data_map(format_data_map(map, "fuzz"), "again.toml")),
                    "the written map reads back different");
  } catch (const DataError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    LPTN_FUZZ_CHECK(false, "the written map does not read back");
  }
  if (cut == std::string_view::npos) return 0;

  // What --suggest-map proposes for the CSV is always a map that reads back (what it cannot decide
  // is said in comments, never written as a broken key).
  try {
    const MapSuggestion proposed = suggest_data_map_text(input.substr(cut + 3), "fuzz.csv");
    try {
      LPTN_FUZZ_CHECK(same(proposed.map, parse_data_map(proposed.text(), "proposed.toml")),
                      "the proposed map reads back different");
    } catch (const DataError& e) {
      std::fprintf(stderr, "%s\n", e.what());
      LPTN_FUZZ_CHECK(false, "the proposed map does not read back");
    }
  } catch (const DataError& e) {
    LPTN_FUZZ_CHECK(one_line(e.what()), "a suggestion's error of more than one line");
  }

  LoadOptions options;
  options.map = std::make_shared<const DataMap>(map);
  options.max_grid_points = 20000;  // a two-row file may span years; bounded here, refused beyond
  try {
    const Dataset d = parse_cycle_csv(input.substr(cut + 3), "fuzz.csv", options);
    for (const Cycle& c : d.cycles) {
      LPTN_FUZZ_CHECK(c.steps >= 1 && c.steps <= options.max_grid_points, "grid size");
      for (Channel ch : kAllChannels) {
        const auto& v = c.samples[index_of(ch)];
        LPTN_FUZZ_CHECK(v.empty() || v.size() == c.steps, "a channel's length");
        for (float x : v)
          LPTN_FUZZ_CHECK(std::isnan(x) || (x >= channel_info(ch).min - 1e-3 && x <= channel_info(ch).max + 1e-3),
                          "a value outside its channel's range");
      }
    }
  } catch (const DataError& e) {
    LPTN_FUZZ_CHECK(one_line(e.what()), "a CSV error of more than one line");
  }
  return 0;
}
