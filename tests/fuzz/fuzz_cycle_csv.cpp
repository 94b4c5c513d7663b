// Fuzz target: the fleet-dump CSV loader (trainer/data/dataset.hpp, parse_cycle_csv). Input: the
// file's text.
//
// Bad input must come out as DataError (the one-line "FILE:LINE: ..." the command line prints);
// anything else escaping is a finding. What loads must be a consistent dataset.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "fuzz_check.hpp"
#include "trainer/data/dataset.hpp"

namespace {

using namespace lptn::data;

// The loader accepts up to 50 million grid points (weeks at 10 Hz, fleet dumps are that long),
// which a two-row input can ask for and which would take seconds and gigabytes per run. Inputs
// whose time span would make more than this many points at the default step are loaded at a
// coarser step instead: still loaded, with the same rows and checks, just faster.
constexpr double kMaxGridPoints = 20000;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// The value of column `column` on a line, or NaN. Rougher than the loader's parsing, which only
// matters where the loader rejects the cell anyway.
double cell_value(std::string_view line, std::size_t column) {
  for (std::size_t c = 0; c < column; ++c) {
    const std::size_t comma = line.find(',');
    if (comma == std::string_view::npos) return NAN;
    line.remove_prefix(comma + 1);
  }
  const std::string cell(trim(line.substr(0, line.find(','))));
  char* end = nullptr;
  const double v = std::strtod(cell.c_str(), &end);
  return end != cell.c_str() ? v : NAN;
}

// The span between the first and the last data row's time_s (time may not go backwards, so that
// is the file's), following the loader's line rules: LF or CRLF, blank lines skipped, a UTF-8
// byte order mark ignored.
double time_span(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  bool have_header = false, have_first = false;
  std::size_t time_column = 0;
  double first = NAN, last = NAN;
  while (!text.empty()) {
    const std::size_t nl = text.find('\n');
    std::string_view line = text.substr(0, nl);
    text.remove_prefix(nl == std::string_view::npos ? text.size() : nl + 1);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (trim(line).empty()) continue;
    if (!have_header) {
      have_header = true;
      bool found = false;
      for (std::string_view rest = line; !found;) {
        std::string_view name = trim(rest.substr(0, rest.find(',')));
        if (name.size() >= 2 && name.front() == '"' && name.back() == '"') name = trim(name.substr(1, name.size() - 2));
        if (name == "time_s") {
          found = true;
        } else if (const std::size_t comma = rest.find(','); comma != std::string_view::npos) {
          rest.remove_prefix(comma + 1);
          ++time_column;
        } else {
          return 0;  // the loader refuses a file without time_s
        }
      }
      continue;
    }
    last = cell_value(line, time_column);
    if (!have_first) first = last;
    have_first = true;
  }
  return have_first ? last - first : 0;
}

void check_dataset(const Dataset& d, const LoadOptions& options) {
  LPTN_FUZZ_CHECK(d.reports.size() == 1, "one report per file");
  for (const Cycle& c : d.cycles) {
    LPTN_FUZZ_CHECK(c.steps > 0, "an empty cycle");
    LPTN_FUZZ_CHECK(c.dt_s == options.dt_s, "the cycle is not on the requested step");
    LPTN_FUZZ_CHECK(std::isfinite(c.t0_s), "grid start");
    for (const auto& samples : c.samples)
      LPTN_FUZZ_CHECK(samples.empty() || samples.size() == c.steps, "a channel neither absent nor on the whole grid");
    for (int i = 0; i < kNumChannels; ++i) {
      const Channel channel = kAllChannels[static_cast<std::size_t>(i)];
      const ChannelInfo& info = channel_info(channel);
      for (float v : c.samples[static_cast<std::size_t>(i)]) {
        // Interpolation between two accepted samples stays between them (float rounding aside).
        const double slack = 1e-5 * std::fmax(std::fabs(info.min), std::fabs(info.max));
        LPTN_FUZZ_CHECK(std::isnan(v) || (v >= info.min - slack && v <= info.max + slack), info.name.data());
      }
    }
  }
  for (const ChannelReport& r : d.reports.front().channels) {
    LPTN_FUZZ_CHECK(r.coverage >= 0 && r.coverage <= 1, "coverage is a fraction");
    LPTN_FUZZ_CHECK(r.native_rate_hz >= 0 && std::isfinite(r.native_rate_hz), "native rate");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  LoadOptions options;
  const double span = time_span(text);
  // NaN or infinite spans make the loader refuse the file whatever the step.
  if (std::isfinite(span) && span / options.dt_s > kMaxGridPoints) options.dt_s = span / kMaxGridPoints;
  try {
    const Dataset d = parse_cycle_csv(text, "fuzz.csv", options);
    check_dataset(d, options);
  } catch (const DataError& e) {
    LPTN_FUZZ_CHECK(std::string_view(e.what()).find_first_of("\r\n") == std::string_view::npos,
                    "an error message of more than one line");
  }
  return 0;
}
