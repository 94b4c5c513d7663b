// Back from the grid to the file: which line of a cycle's CSV a value on the grid came from, for
// the error messages of tools that read cycles through the loader (lptn convert).
#pragma once

#include <cstddef>
#include <filesystem>

#include "trainer/data/channels.hpp"

namespace lptn::data {

// The 1-based line of `csv` whose sample of `channel` outside [min, max] lies nearest to time
// `t_s`; 0 if no sample lies outside. Linear interpolation between values within a range stays
// within it, so a grid value outside the range has such a sample. Parses the file anew (an
// error path, not for loops).
std::size_t line_of_sample_outside(const std::filesystem::path& csv, Channel channel, double t_s, double min, double max);

}  // namespace lptn::data
