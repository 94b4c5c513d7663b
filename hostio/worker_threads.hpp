// How many threads the host's parallel work uses (loading a fleet dump, LM's residual blocks,
// metrics per cycle, the diagnosis's refits): every core the machine has. The one place this is
// decided, so that the trainer's parts agree.
#pragma once

#include <thread>

namespace lptn {

inline int worker_threads() {
  const unsigned n = std::thread::hardware_concurrency();  // 0 where the machine does not say
  return n == 0 ? 1 : static_cast<int>(n);
}

}  // namespace lptn
