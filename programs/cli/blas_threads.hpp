// `lptn` links OpenBLAS (through Ceres's LAPACK, for calibrate and diagnose), and Debian's pthread
// OpenBLAS starts its worker threads when the library loads, before main(); each then spins in
// sched_yield for about 0.13 s before it sleeps. A command that does no linear algebra (replay,
// convert) stops them at once: on a busy machine the spinning took a core from the work (perf
// showed sched_yield at 15 % of a replay), and in a replay of many logs it competed with the
// replay's own threads. OpenBLAS starts them again if a later call needs them; an lptn without
// OpenBLAS (another BLAS, a static one) has no such symbol and nothing is done.
#pragma once

#include <dlfcn.h>

#include <cstring>

namespace lptn::cli {

inline void stop_blas_threads() {
  using Shutdown = int (*)();
  void* symbol = dlsym(RTLD_DEFAULT, "blas_thread_shutdown_");
  if (symbol == nullptr) return;
  Shutdown shutdown;  // an object pointer to a function pointer, as POSIX allows and -Wpedantic accepts
  std::memcpy(&shutdown, &symbol, sizeof shutdown);
  shutdown();
}

}  // namespace lptn::cli
