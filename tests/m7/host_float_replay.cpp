// The bare-metal replay image's host twin: the same run_float_replay (firmware/baremetal/
// float_replay.hpp), the same float estimator and compiled-in calibration, reading and writing
// with stdio instead of semihosting. scripts/check-m7-golden.sh holds the image under qemu to it.
//   lptn_host_float_replay LOG OUT.csv [--open-loop]
#include <cstdio>
#include <cstring>

#include LPTN_CALIBRATION_HEADER
#include "../../firmware/baremetal/float_replay.hpp"
#include "lptn/firmware/exported_calibration.hpp"

namespace {

struct StdioIo {
  std::FILE* log = nullptr;
  std::FILE* out = nullptr;
  std::size_t read(char* buf, std::size_t n) { return std::fread(buf, 1, n, log); }
  void write(const char* s, std::size_t n) { std::fwrite(s, 1, n, out); }
  void tick_started() {}
  void tick_ended() {}
};

}  // namespace

int main(int argc, char** argv) {
  const bool open_loop = argc == 4 && std::strcmp(argv[3], "--open-loop") == 0;
  if (argc < 3 || (argc == 4 && !open_loop) || argc > 4) {
    std::fprintf(stderr, "usage: lptn_host_float_replay LOG OUT.csv [--open-loop]\n");
    return 2;
  }
  StdioIo io;
  io.log = std::fopen(argv[1], "rb");
  io.out = std::fopen(argv[2], "wb");
  if (!io.log || !io.out) {
    std::fprintf(stderr, "lptn_host_float_replay: cannot open %s\n", io.log ? argv[2] : argv[1]);
    return 2;
  }
  static lptn::fw::EstimatorConfig<float> config = lptn::fw::config_from_exported_header<float>();
  config.fuse_stator_sensor = !open_loop;
  static lptn::fw::Estimator<float> estimator(config);
  const lptn::fw::FloatReplayResult r = lptn::fw::run_float_replay(io, estimator);
  std::fclose(io.log);
  const bool written = std::fclose(io.out) == 0;
  std::printf("host float replay: %zu frames, %zu ticks, %zu estimates, %zu bad lines\n", r.counts.frames,
              r.counts.ticks, r.counts.rows, r.bad_lines);
  return written && r.counts.frames > 0 ? 0 : 1;
}
