// lptn_report_make_dump DIR: the report tests' dump (dump.hpp), as ctest's fixture set-up.
#include <cstdio>

#include "dump.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: lptn_report_make_dump DIR\n");
    return 2;
  }
  const std::string error = lptn::testing::make_report_dump(argv[1]);
  if (!error.empty()) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  return 0;
}
