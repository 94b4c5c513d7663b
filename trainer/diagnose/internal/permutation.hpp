// Exact tests under exchangeable cycles: a statistic of the cycles in the dump's order against its
// values over random orderings (the drift's and the sensor check's tests).
#pragma once

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace lptn::diagnose::internal {

inline constexpr int kOrderings = 4000;
inline constexpr std::uint64_t kOrderingSeed = 20261123;

// The share of orderings of `items` whose statistic reaches `observed` (the observed ordering
// counts): exact under "the order does not matter", whatever the statistic.
template <class T, class F>
double p_value(std::vector<T> items, double observed, F&& statistic) {
  std::mt19937_64 rng(kOrderingSeed);
  int reached = 1;
  for (int i = 0; i < kOrderings; ++i) {
    std::shuffle(items.begin(), items.end(), rng);
    reached += statistic(items) >= observed * (1 - 1e-12);
  }
  return static_cast<double>(reached) / (kOrderings + 1);
}

}  // namespace lptn::diagnose::internal
