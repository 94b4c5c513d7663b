// How many threads the host's parallel work uses (loading a fleet dump, LM's residual blocks,
// metrics per cycle, the diagnosis's refits): every core the machine has. The one place this is
// decided, so that the trainer's parts agree.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <thread>
#include <vector>

namespace lptn::hostio {

// Under an MPI launcher the processes on one machine share its cores: each takes its share
// (Open MPI and MPICH say how many ranks run on this node).
inline int worker_threads() {
  const unsigned n = std::thread::hardware_concurrency();  // 0 where the machine does not say
  int cores = n == 0 ? 1 : static_cast<int>(n);
  for (const char* name : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"})
    if (const char* value = std::getenv(name); value != nullptr)
      if (const int ranks = std::atoi(value); ranks > 1) return std::max(1, cores / ranks);
  return cores;
}

// Calls work(i) for i in 0..n-1 over `threads` threads (the calling one among them), index i on
// thread i mod threads: for independent items that each write only their own slot.
template <class Work>
void parallel_for(std::size_t n, int threads, Work&& work) {
  const std::size_t workers = std::min<std::size_t>(n, static_cast<std::size_t>(std::max(1, threads)));
  auto share = [&](std::size_t w) {
    for (std::size_t i = w; i < n; i += workers) work(i);
  };
  std::vector<std::thread> pool;
  for (std::size_t w = 1; w < workers; ++w) pool.emplace_back(share, w);
  if (workers > 0) share(0);
  for (std::thread& t : pool) t.join();
}

}  // namespace lptn::hostio
