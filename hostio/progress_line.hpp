// A status line for long work: redrawn in place on a terminal, and on a pipe or a log file one
// plain line every few seconds, so that CI logs show progress without a flood of carriage returns.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

namespace lptn::hostio {

class ProgressLine {
 public:
  explicit ProgressLine(bool quiet = false) : quiet_(quiet), tty_(::isatty(STDERR_FILENO) == 1) {}
  ~ProgressLine() { finish(); }

  void update(const std::string& text, bool force = false) {
    if (quiet_) return;
    const auto now = std::chrono::steady_clock::now();
    if (tty_) {
      std::fprintf(stderr, "\r%s\x1b[K", text.c_str());
      open_ = true;
    } else if (force || now - last_ >= std::chrono::seconds(5)) {
      std::fprintf(stderr, "%s\n", text.c_str());
      last_ = now;
    }
    std::fflush(stderr);
  }

  // Ends the line on a terminal (the last state stays visible).
  void finish() {
    if (open_) std::fprintf(stderr, "\n");
    open_ = false;
  }

  // "[#####.....]" for a fraction in [0, 1].
  static std::string bar(double fraction, int width = 20) {
    const int filled = static_cast<int>(fraction * width + 0.5);
    std::string s = "[";
    for (int i = 0; i < width; ++i) s += i < filled ? '#' : '.';
    return s + "]";
  }

  // "1:05:09" or "4:09".
  static std::string clock(double seconds) {
    const long s = static_cast<long>(seconds + 0.5);
    char buf[32];
    if (s >= 3600) std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
    else std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
    return buf;
  }

 private:
  bool quiet_, tty_, open_ = false;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace lptn::hostio
