#pragma once
// Fleet-dump loading: one CSV per driving cycle, resampled per channel onto a fixed time grid.

#include <array>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "hostio/bad_input.hpp"
#include "trainer/data/channels.hpp"

namespace lptn::data {

struct DataMap;

// The grid step a dump is resampled to unless told otherwise, s.
inline constexpr double kDefaultDtS = 0.1;

struct LoadOptions {
  double dt_s = kDefaultDtS;
  std::array<double, kNumChannels> max_gap_s = default_max_gaps();
  // Only pieces cut out by a split are held to this; an unsplit file is kept however short.
  double min_segment_s = 60.0;
  // How to read the files (trainer/data/data_map.hpp). Null: each file through the data.toml
  // beside it if there is one (unless map_beside is false), else as lptn's own CSV.
  std::shared_ptr<const DataMap> map;
  bool map_beside = true;
  // The longest time grid one file may span before its time column is taken for broken (a typo,
  // or milliseconds read as seconds): 50 million points, weeks at 10 Hz.
  std::size_t max_grid_points = 50'000'000;
};

// The data map a file is read through under `options`, or null.
std::shared_ptr<const DataMap> data_map_for(const std::filesystem::path& file, const LoadOptions& options);
// `options` reading every file through the map in `map_file` (--map; throws DataError for a bad
// map, as load_data_map); an empty path leaves them as they are (each file's data.toml, if any).
LoadOptions with_data_map(const std::filesystem::path& map_file, LoadOptions options = {});

// One resampled driving cycle, or one segment of it after a split.
struct Cycle {
  // The file's stem (or the drive's name, "stem-<trip>" or "stem-2", after a data map's [split]);
  // "name-2", "name-3"... for the segments after the first when a gap splits it.
  std::string name;
  std::filesystem::path file;
  // The data map the file was read through: where from, and data_map_sha256() of it (what it
  // reads the file as); both empty where the file was read as lptn's own CSV.
  std::filesystem::path map_file;
  std::string map_sha256;
  double t0_s = 0, dt_s = 0.1;  // grid: t0 + k*dt, k < steps; t0 is on the file's grid
  std::size_t steps = 0;
  // NaN = missing or masked. Either empty (the column is absent from the file) or `steps` long.
  // float rather than double on purpose: fleet dumps hold hundreds of hours.
  std::array<std::vector<float>, kNumChannels> samples;

  bool has(Channel c) const;  // at least one valid sample
  // NaN for an absent channel; throws past the end. Inline: the simulations ask it for every
  // sensor at every step (out of line, the call was 3.4 % of a 200 h diagnosis).
  float at(Channel c, std::size_t k) const {
    const std::vector<float>& v = samples[index_of(c)];
    if (k >= (v.empty() ? steps : v.size())) [[unlikely]]
      throw_past_end(k);
    return v.empty() ? std::numeric_limits<float>::quiet_NaN() : v[k];
  }
  double time_s(std::size_t k) const { return t0_s + static_cast<double>(k) * dt_s; }
  double duration_s() const { return steps > 1 ? static_cast<double>(steps - 1) * dt_s : 0.0; }

 private:
  [[noreturn]] void throw_past_end(std::size_t k) const;
};

struct Gap {
  double start_s, end_s;  // times of the samples either side
  std::size_t line_before, line_after;  // their 1-based line numbers in the file
  enum class Action { bridged, masked, split } action;
};

struct ChannelReport {
  Channel channel;
  bool present = false;  // the column is in the file
  std::size_t samples = 0;  // non-empty cells
  double native_rate_hz = 0;  // 1 / median interval between its samples; 0 with fewer than two
  double coverage = 0;  // fraction of the file's grid points with a valid value
  // Every interval between consecutive samples longer than 3x the median interval or longer
  // than the bridging limit, bridged ones included.
  std::vector<Gap> gaps;
};

struct Finding {
  enum class Severity { info, warning } severity;
  std::string message;  // names the file (and line/column where there is one)
};

// One per file, whatever it was split into.
struct CycleReport {
  std::string name;
  std::filesystem::path file;
  double duration_s = 0;  // last time_s - first time_s
  std::size_t rows = 0;  // data rows
  std::array<ChannelReport, kNumChannels> channels;
  std::vector<Finding> findings;
};

struct Dataset {
  std::vector<Cycle> cycles;
  std::vector<CycleReport> reports;  // of the files loaded here
  std::size_t warning_count() const;
};

// Message is one line: "FILE:LINE: column 'NAME': reason" (the column part is left out when no
// column is involved, e.g. a row with the wrong number of cells). Problems of a whole column (missing,
// duplicate, entirely empty) and of the whole file (empty, header only) point at the header line.
class DataError : public hostio::BadInput {
 public:
  using BadInput::BadInput;
};

// The files load_fleet_dump reads for `paths`, in its order: each path a CSV file or a directory
// (its *.csv files, sorted by name, not recursive), none twice. Throws DataError for a path that
// does not exist or a directory without *.csv files.
std::vector<std::filesystem::path> cycle_files(const std::vector<std::filesystem::path>& paths);

// Each path is a CSV file or a directory (its *.csv files, sorted by name, not recursive).
// Throws DataError on the first bad file, std::invalid_argument on bad options.
Dataset load_fleet_dump(const std::vector<std::filesystem::path>& paths, const LoadOptions& = {});

// One file. The result holds one report and zero or more cycles.
Dataset load_cycle_file(const std::filesystem::path& file, const LoadOptions& = {});

// CSV text already in memory; `file` is only used for names and messages.
Dataset parse_cycle_csv(std::string_view text, const std::filesystem::path& file,
                        const LoadOptions& = {});

}  // namespace lptn::data
