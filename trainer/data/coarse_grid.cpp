#include "trainer/data/coarse_grid.hpp"

#include <cmath>
#include <stdexcept>

namespace lptn::data {

Cycle coarse_grid(const Cycle& cycle, int factor) {
  if (factor < 1) throw std::invalid_argument("coarse_grid: factor must be at least 1");
  if (factor == 1) return cycle;
  const auto f = static_cast<std::size_t>(factor);
  Cycle out;
  out.name = cycle.name;
  out.file = cycle.file;
  out.t0_s = cycle.t0_s;
  out.dt_s = cycle.dt_s * factor;
  out.steps = cycle.steps == 0 ? 0 : (cycle.steps - 1) / f + 1;
  for (Channel c : kAllChannels) {
    const std::vector<float>& fine = cycle.samples[index_of(c)];
    std::vector<float>& coarse = out.samples[index_of(c)];
    if (fine.empty()) continue;
    coarse.resize(out.steps);
    const bool measured = c == Channel::stator_winding_c || c == Channel::rotor_c;
    for (std::size_t k = 0; k < out.steps; ++k) {
      if (measured) {
        coarse[k] = fine[k * f];
        continue;
      }
      double sum = 0;
      std::size_t n = 0;
      for (std::size_t i = k * f; i < std::min(cycle.steps, (k + 1) * f); ++i) {
        if (std::isnan(fine[i])) continue;
        sum += c == Channel::current_a ? double(fine[i]) * fine[i] : double(fine[i]);
        ++n;
      }
      coarse[k] = n == 0 ? std::nanf("") : static_cast<float>(c == Channel::current_a ? std::sqrt(sum / n) : sum / n);
    }
  }
  return out;
}

}  // namespace lptn::data
