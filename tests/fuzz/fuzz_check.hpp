// The fuzz targets' one assertion. Not assert(): the fuzz preset builds RelWithDebInfo, whose
// NDEBUG would compile it away. abort() is what libFuzzer reports as a crash and saves the input.
#pragma once

#include <cstdio>
#include <cstdlib>

#define LPTN_FUZZ_CHECK(condition, what)                                                          \
  do {                                                                                            \
    if (!(condition)) {                                                                           \
      std::fprintf(stderr, "%s:%d: fuzz check failed: %s (%s)\n", __FILE__, __LINE__, #condition, \
                   what);                                                                         \
      std::abort();                                                                               \
    }                                                                                             \
  } while (false)
