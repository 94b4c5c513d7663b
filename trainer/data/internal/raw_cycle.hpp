#pragma once
// The two halves of loading one file: parsing the CSV into per-channel sample lists, then
// resampling those onto the grid (and splitting, masking, reporting).

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "trainer/data/channels.hpp"
#include "trainer/data/data_map.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn::data::internal {

struct RawChannel {
  bool present = false;  // the column is in the header
  // Sample i was in data row rows[i]; 32 bits halve the footprint and a CSV never has 4G rows.
  std::vector<std::uint32_t> rows;
  std::vector<double> values;
};

struct RawCycle {
  std::filesystem::path file;
  std::string name;  // the file's stem, or the drive's name after a data map's [split]
  std::vector<double> time;  // per data row, non-decreasing
  std::vector<std::uint32_t> line;  // per data row, its 1-based line in the file
  std::array<RawChannel, kNumChannels> channels;
  std::vector<Finding> findings;  // what parsing noticed but tolerated
};

// Throws DataError for everything the data contract calls an error. Read as `map` says (null: lptn's
// own columns, comma-separated, seconds); one RawCycle per drive its [split] cuts the file into.
std::vector<RawCycle> parse_csv(std::string_view text, const std::filesystem::path& file, const DataMap* map);

// One channel's samples with equal timestamps merged (values averaged).
struct Series {
  std::vector<double> t, v;
  std::vector<std::uint32_t> first_line, last_line;  // of the rows merged into each sample
  // Time stamps that carried more than one reading (merged into their mean), and how many of
  // those disagreed; the first disagreement for the message: its time, lines and readings.
  std::size_t repeated = 0, conflicting = 0;
  double conflict_t = 0, conflict_a = 0, conflict_b = 0;
  std::uint32_t conflict_line_a = 0, conflict_line_b = 0;
};
Series merge_duplicates(const RawCycle& raw, Channel c);

// Linear interpolation of `s` at t0 + k*dt for k < steps into out[k]; NaN before the first
// sample, after the last, and strictly inside any interval longer than max_gap_s.
void resample(const Series& s, double t0, double dt, std::size_t steps, double max_gap_s, float* out);

// Throws DataError when the grid would be unreasonably large (a typo in time_s).
Dataset assemble(RawCycle&& raw, const LoadOptions& options);


}  // namespace lptn::data::internal
