// File and directory handling around the CSV parser and the resampler.

#include "trainer/data/dataset.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstring>
#include <exception>
#include <fstream>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <system_error>

#include "hostio/worker_threads.hpp"
#include "trainer/data/data_map.hpp"
#include "trainer/data/internal/raw_cycle.hpp"

namespace lptn::data {
namespace fs = std::filesystem;

bool Cycle::has(Channel c) const {
  const auto& v = samples[index_of(c)];
  return std::any_of(v.begin(), v.end(), [](float x) { return !std::isnan(x); });
}

void Cycle::throw_past_end(std::size_t k) const {
  throw std::out_of_range("Cycle::at: step " + std::to_string(k) + " past the end of " + name);
}

std::size_t Dataset::warning_count() const {
  std::size_t n = 0;
  for (const CycleReport& r : reports) {
    n += static_cast<std::size_t>(std::count_if(r.findings.begin(), r.findings.end(), [](const Finding& f) {
      return f.severity == Finding::Severity::warning;
    }));
  }
  return n;
}

namespace {

void check(const LoadOptions& o) {
  if (!(o.dt_s > 0) || !std::isfinite(o.dt_s)) throw std::invalid_argument("LoadOptions: dt_s must be positive");
  for (Channel c : kAllChannels) {
    // +inf is meaningful (never give up bridging), NaN and negatives are not.
    if (!(o.max_gap_s[index_of(c)] >= 0)) {
      throw std::invalid_argument("LoadOptions: max_gap_s for " + std::string(channel_name(c)) +
                                  " must be zero or positive");
    }
  }
  if (!(o.min_segment_s >= 0)) throw std::invalid_argument("LoadOptions: min_segment_s must be zero or positive");
}

// Read in chunks, each scanned for line ends as it arrives: a file with an endless line (corrupt,
// or not a CSV at all) is refused after its first megabyte instead of being read whole.
constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;

std::string read_whole_file(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) {
    throw DataError(file.string() + (fs::exists(file, ec) ? ": not a regular file" : ": no such file"));
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) throw DataError(file.string() + ": cannot open for reading");
  const auto size = fs::file_size(file, ec);
  std::string text;
  constexpr std::size_t kChunk = std::size_t{4} << 20;
  std::size_t line_start = 0, lines = 0;
  for (bool first = true;; first = false) {
    // The whole size is reserved once the first chunk has shown a CSV's short lines (not before:
    // under AddressSanitizer even untouched reserved memory costs an eighth of its size), with a
    // chunk beyond, so that the last read's resize does not reallocate.
    if (!first && !ec && text.capacity() < static_cast<std::size_t>(size) + kChunk)
      text.reserve(static_cast<std::size_t>(size) + kChunk);
    const std::size_t at = text.size();
    text.resize(at + kChunk);
    in.read(text.data() + at, static_cast<std::streamsize>(kChunk));
    const auto got = static_cast<std::size_t>(in.gcount());
    text.resize(at + got);
    const char* const end = text.data() + text.size();
    for (const char* p = text.data() + at; p < end; ++p) {
      p = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
      if (p == nullptr) break;
      line_start = static_cast<std::size_t>(p - text.data()) + 1;
      ++lines;
    }
    if (text.size() - line_start > kMaxLineBytes)
      throw DataError(file.string() + ":" + std::to_string(lines + 1) +
                      ": line longer than 1 MiB (a fleet-dump row is a few hundred bytes): not a CSV, or a broken file");
    if (got < kChunk) break;
  }
  if (in.bad()) throw DataError(file.string() + ": read error");
  return text;
}

bool is_csv(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".csv";
}

std::vector<fs::path> expand(const std::vector<fs::path>& paths) {
  std::vector<fs::path> files;
  for (const fs::path& p : paths) {
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      std::vector<fs::path> found;
      for (const fs::directory_entry& e : fs::directory_iterator(p)) {
        if (e.is_regular_file() && is_csv(e.path())) found.push_back(e.path());
      }
      if (found.empty()) throw DataError(p.string() + ": no *.csv files in this directory");
      std::sort(found.begin(), found.end(),
                [](const fs::path& a, const fs::path& b) { return a.filename() < b.filename(); });
      files.insert(files.end(), found.begin(), found.end());
    } else if (fs::exists(p, ec)) {
      // An explicitly named file is taken whatever its extension: the user asked for it.
      files.push_back(p);
    } else {
      throw DataError(p.string() + ": no such file or directory");
    }
  }
  return files;
}

void append(Dataset& into, Dataset&& from) {
  for (Cycle& c : from.cycles) into.cycles.push_back(std::move(c));
  for (CycleReport& r : from.reports) into.reports.push_back(std::move(r));
}

}  // namespace

LoadOptions with_data_map(const fs::path& map_file, LoadOptions options) {
  if (!map_file.empty()) options.map = std::make_shared<const DataMap>(load_data_map(map_file));
  return options;
}

std::shared_ptr<const DataMap> data_map_for(const fs::path& file, const LoadOptions& options) {
  if (options.map) return options.map;
  if (!options.map_beside) return nullptr;
  const fs::path beside = file.parent_path() / kDataMapFileName;
  std::error_code ec;
  if (!fs::is_regular_file(beside, ec)) return nullptr;
  return std::make_shared<const DataMap>(load_data_map(beside));
}

namespace {

Dataset parse_and_assemble(std::string_view text, const fs::path& file, const LoadOptions& options,
                           const DataMap* map) {
  Dataset out;
  const std::string map_sha256 = map != nullptr ? data_map_sha256(*map) : std::string();
  for (internal::RawCycle& raw : internal::parse_csv(text, file, map)) {
    Dataset one = internal::assemble(std::move(raw), options);
    for (Cycle& c : one.cycles) {
      if (map != nullptr) c.map_file = map->file;
      c.map_sha256 = map_sha256;
    }
    if (map != nullptr && out.reports.empty())
      one.reports.front().findings.insert(
          one.reports.front().findings.begin(),
          {Finding::Severity::info,
           file.string() + ": read through the data map " + (map->file.empty() ? std::string("given") : map->file.string())});
    append(out, std::move(one));
  }
  return out;
}

}  // namespace

Dataset parse_cycle_csv(std::string_view text, const fs::path& file, const LoadOptions& options) {
  check(options);
  return parse_and_assemble(text, file, options, options.map.get());
}

Dataset load_cycle_file(const fs::path& file, const LoadOptions& options) {
  check(options);
  const std::shared_ptr<const DataMap> map = data_map_for(file, options);
  const std::string text = read_whole_file(file);
  return parse_and_assemble(text, file, options, map.get());
}

std::vector<fs::path> cycle_files(const std::vector<fs::path>& paths) {
  std::vector<fs::path> files;
  std::set<fs::path> seen;
  for (const fs::path& file : expand(paths)) {
    std::error_code ec;
    fs::path key = fs::weakly_canonical(file, ec);
    if (ec) key = file;
    if (seen.insert(key).second) files.push_back(file);  // not named twice (a directory and a file in it, say)
  }
  return files;
}

Dataset load_fleet_dump(const std::vector<fs::path>& paths, const LoadOptions& options) {
  check(options);
  const std::vector<fs::path> files = cycle_files(paths);

  // Files are loaded on every core, each into its own slot; the result is assembled in file order,
  // and the first bad file in that order is the one reported, as if loaded one by one.
  std::vector<Dataset> loaded(files.size());
  std::vector<std::exception_ptr> failed(files.size());
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t i; (i = next++) < files.size();) {
      try {
        loaded[i] = load_cycle_file(files[i], options);
      } catch (...) {
        failed[i] = std::current_exception();
      }
    }
  };
  const std::size_t threads = std::min<std::size_t>(files.size(), static_cast<std::size_t>(hostio::worker_threads()));
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();

  Dataset all;
  for (std::size_t f = 0; f < files.size(); ++f) {
    if (failed[f]) std::rethrow_exception(failed[f]);
    Dataset& one = loaded[f];
    for (CycleReport& r : one.reports) {
      const auto clash = std::find_if(all.reports.begin(), all.reports.end(),
                                      [&](const CycleReport& o) { return o.name == r.name; });
      if (clash != all.reports.end()) {
        r.findings.push_back({Finding::Severity::warning,
                              r.file.string() + ": cycle name '" + r.name + "' is also the name of " +
                                  clash->file.string() + "; only the file tells their cycles apart"});
      }
    }
    append(all, std::move(one));
  }
  return all;
}

}  // namespace lptn::data
