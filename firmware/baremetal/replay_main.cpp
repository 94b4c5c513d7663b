// The Cortex-M7 replay image (qemu's mps2-an500, scripts/run-m7.sh): a candump log through the float
// estimator with the compiled-in calibration, as the product image runs it, reading the log and
// writing the estimates through semihosting. Command line (qemu's semihosting args):
//   IMAGE LOG OUT.csv [--open-loop]
// It reports the estimator's cycles per tick (SysTick on the core clock; under qemu's -icount, a
// count of instructions) and the stack's high-water mark (the stack painted at start).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

#include LPTN_CALIBRATION_HEADER  // firmware/CMakeLists.txt: an `lptn export`
#include "float_replay.hpp"
#include "lptn/firmware/exported_calibration.hpp"
#include "semihosting.hpp"

extern "C" std::uint32_t end, __stack;  // m7_sections.ld: the end of .bss, the top of the stack

namespace {

namespace sh = lptn::semihosting;

// SysTick, counting down the core clock from 2^24 - 1.
volatile std::uint32_t& kSystCsr = *reinterpret_cast<volatile std::uint32_t*>(0xE000E010);
volatile std::uint32_t& kSystRvr = *reinterpret_cast<volatile std::uint32_t*>(0xE000E014);
volatile std::uint32_t& kSystCvr = *reinterpret_cast<volatile std::uint32_t*>(0xE000E018);
constexpr std::uint32_t kSysTickMask = 0xFFFFFF;
constexpr std::uint32_t kPaint = 0xA5A5A5A5u;

void say(int handle, std::string_view s) { sh::write(handle, s.data(), s.size()); }

void say_number(int handle, unsigned long long v) {
  char digits[24];
  int n = 0;
  do {
    digits[n++] = static_cast<char>('0' + v % 10);
    v /= 10;
  } while (v > 0);
  char out[24];
  for (int i = 0; i < n; ++i) out[i] = digits[n - 1 - i];
  sh::write(handle, out, static_cast<std::size_t>(n));
}

struct SemihostingIo {
  int log = -1, out = -1;
  char buffer[8192];
  std::size_t used = 0;
  bool write_failed = false;
  std::uint32_t started = 0;
  unsigned long long cycles = 0;

  std::size_t read(char* buf, std::size_t n) { return sh::read(log, buf, n); }
  void write(const char* s, std::size_t n) {
    if (used + n > sizeof buffer) flush();
    std::memcpy(buffer + used, s, n);
    used += n;
  }
  void flush() {
    if (used > 0 && !sh::write(out, buffer, used)) write_failed = true;
    used = 0;
  }
  void tick_started() { started = kSystCvr; }
  void tick_ended() { cycles += (started - kSystCvr) & kSysTickMask; }
};

SemihostingIo io;

}  // namespace

int main() {
  // Paint the stack below this frame, for the high-water mark at the end.
  std::uint32_t here = 0;
  for (std::uint32_t* p = &end; p + 64 < &here; ++p) *p = kPaint;

  const int tty = sh::open(":tt", 4);
  char command[512] = {};
  if (!sh::command_line(command, sizeof command - 1)) sh::exit(2);
  std::string_view args[4];
  int n = 0;
  for (char* p = command; *p != '\0' && n < 4;) {
    while (*p == ' ') ++p;
    char* start = p;
    while (*p != '\0' && *p != ' ') ++p;
    if (p > start) args[n++] = std::string_view(start, static_cast<std::size_t>(p - start));
    if (*p == ' ') *p++ = '\0';
  }
  const bool open_loop = n == 4 && args[3] == "--open-loop";
  if (n < 3 || (n == 4 && !open_loop)) {
    say(tty, "usage: IMAGE LOG OUT.csv [--open-loop]\n");
    sh::exit(2);
  }
  io.log = sh::open(args[1].data(), 1);
  if (io.log < 0) {
    say(tty, "lptn m7 replay: cannot open the log\n");
    sh::exit(2);
  }
  io.out = sh::open(args[2].data(), 5);
  if (io.out < 0) {
    say(tty, "lptn m7 replay: cannot open the output\n");
    sh::exit(2);
  }

  kSystRvr = kSysTickMask;
  kSystCvr = 0;
  kSystCsr = 0x5;  // enabled, on the core clock, no interrupt

  static lptn::fw::EstimatorConfig<float> config = lptn::fw::config_from_exported_header<float>();
  config.fuse_stator_sensor = !open_loop;
  static lptn::fw::Estimator<float> estimator(config);
  const lptn::fw::FloatReplayResult r = lptn::fw::run_float_replay(io, estimator);
  io.flush();
  sh::close(io.out);
  sh::close(io.log);

  const std::uint32_t* lowest = &end;
  while (lowest < &__stack && *lowest == kPaint) ++lowest;
  const auto stack_bytes = static_cast<unsigned long long>(reinterpret_cast<std::uintptr_t>(&__stack) -
                                                           reinterpret_cast<std::uintptr_t>(lowest));
  say(tty, "m7 replay: ");
  say_number(tty, r.counts.frames);
  say(tty, " frames, ");
  say_number(tty, r.counts.ticks);
  say(tty, " ticks, ");
  say_number(tty, r.counts.rows);
  say(tty, " estimates, ");
  say_number(tty, r.bad_lines);
  say(tty, " bad lines\nm7 replay: estimator cycles ");
  say_number(tty, io.cycles);
  say(tty, " in all, ");
  say_number(tty, r.counts.ticks ? io.cycles / r.counts.ticks : 0);
  say(tty, " per tick\nm7 replay: stack high-water ");
  say_number(tty, stack_bytes);
  say(tty, " bytes\n");
  sh::exit(io.write_failed || r.counts.frames == 0 ? 1 : 0);
}
