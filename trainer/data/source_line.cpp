#include "trainer/data/source_line.hpp"

#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

#include "trainer/data/internal/raw_cycle.hpp"

namespace lptn::data {

std::size_t line_of_sample_outside(const std::filesystem::path& csv, Channel channel, double t_s, double min,
                                   double max) {
  std::ifstream in(csv, std::ios::binary);
  const std::string text(std::istreambuf_iterator<char>(in), {});
  const auto map = data_map_for(csv, LoadOptions{});
  const std::vector<internal::RawCycle> drives = internal::parse_csv(text, csv, map.get());
  internal::RawCycle raw = drives.front();
  for (std::size_t d = 1; d < drives.size(); ++d) {  // the file's rows whole again: times are what is searched
    for (std::size_t c = 0; c < raw.channels.size(); ++c) {
      const auto rows = static_cast<std::uint32_t>(raw.time.size());
      for (std::uint32_t r : drives[d].channels[c].rows) raw.channels[c].rows.push_back(r + rows);
      raw.channels[c].values.insert(raw.channels[c].values.end(), drives[d].channels[c].values.begin(),
                                    drives[d].channels[c].values.end());
    }
    raw.time.insert(raw.time.end(), drives[d].time.begin(), drives[d].time.end());
    raw.line.insert(raw.line.end(), drives[d].line.begin(), drives[d].line.end());
  }
  const internal::RawChannel& ch = raw.channels[index_of(channel)];
  std::size_t line = 0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < ch.values.size(); ++i) {
    if (ch.values[i] >= min && ch.values[i] <= max) continue;
    const double distance = std::fabs(raw.time[ch.rows[i]] - t_s);
    if (distance < best) {
      best = distance;
      line = raw.line[ch.rows[i]];
    }
  }
  return line;
}

}  // namespace lptn::data
