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
  const internal::RawCycle raw = internal::parse_csv(text, csv);
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
