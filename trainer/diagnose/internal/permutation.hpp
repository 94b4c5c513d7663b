// Exact tests under exchangeable cycles: a statistic of the cycles in the dump's order against its
// values over random orderings (the drift's and the sensor check's tests).
#pragma once

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "hostio/worker_threads.hpp"

namespace lptn::diagnose::internal {

inline constexpr int kOrderings = 4000;
inline constexpr std::uint64_t kOrderingSeed = 20261123;

// The share of orderings of `items` whose statistic reaches `observed` (the observed ordering
// counts): exact under "the order does not matter", whatever the statistic. The orderings are
// drawn one after another from one seed, as ever, and their statistics computed on `threads`
// threads (a statistic of 160 cycles is O(n^2): serial, the 4000 of them were seconds of a 200 h
// diagnosis with the other core idle); the count does not depend on the threads.
template <class T, class F>
double p_value(std::vector<T> items, double observed, F&& statistic, int threads = 1) {
  std::mt19937_64 rng(kOrderingSeed);
  // In batches, so that the orderings held at once stay a few MB whatever the items.
  constexpr int kBatch = 500;
  std::vector<std::vector<T>> batch(kBatch);
  std::vector<char> reaches(kBatch);
  int reached = 1;
  for (int first = 0; first < kOrderings; first += kBatch) {
    const int size = std::min(kBatch, kOrderings - first);
    for (int i = 0; i < size; ++i) {
      std::shuffle(items.begin(), items.end(), rng);
      batch[static_cast<std::size_t>(i)] = items;
    }
    hostio::parallel_for(static_cast<std::size_t>(size), threads, [&](std::size_t i) {
      reaches[i] = statistic(batch[i]) >= observed * (1 - 1e-12);
    });
    for (int i = 0; i < size; ++i) reached += reaches[static_cast<std::size_t>(i)];
  }
  return static_cast<double>(reached) / (kOrderings + 1);
}

}  // namespace lptn::diagnose::internal
