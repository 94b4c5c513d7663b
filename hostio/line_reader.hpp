// Reads a text file line by line into a fixed buffer. No allocation (the daemon reads logs on the
// target), and a line longer than the buffer, which no candump log has, costs no memory: it is
// read to its end, dropped and reported, however long it is (a corrupt or hostile file).
#pragma once

#include <cstddef>
#include <cstdio>
#include <string_view>

namespace lptn::hostio {

class LineReader {
 public:
  // A candump line is at most about 160 characters (CAN FD, 64 data bytes, a long interface name).
  static constexpr std::size_t kMaxLine = 512;
  enum class Status { line, too_long, end };

  explicit LineReader(std::FILE* f) : f_(f) {}

  // `line`: `text` is the next line, without its '\n' (and valid until the next call);
  // `too_long`: the next line exceeded kMaxLine bytes and was skipped; `end`: end of file or error.
  Status next(std::string_view& text) {
    std::size_t n = 0;
    int c;
    while ((c = getc_unlocked(f_)) != EOF) {
      if (c == '\n') break;
      if (n == kMaxLine) {  // drop the rest of this line
        while ((c = getc_unlocked(f_)) != EOF && c != '\n') {
        }
        ++number_;
        return Status::too_long;
      }
      buf_[n++] = static_cast<char>(c);
    }
    if (c == EOF && n == 0) return Status::end;
    ++number_;
    text = std::string_view(buf_, n);
    return Status::line;
  }

  // 1-based number of the line last returned (or skipped).
  std::size_t line_number() const { return number_; }

 private:
  std::FILE* f_;
  char buf_[kMaxLine];
  std::size_t number_ = 0;
};

}  // namespace lptn::hostio
