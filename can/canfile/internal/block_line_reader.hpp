// hostio/LineReader's lines (the same lines, numbers and too-long rule), read from a file a block
// of 256 KiB at a time and cut with memchr: LineReader's character-at-a-time getc is what the
// target's daemon can afford; on the host the readers of candump and ASC logs spent more in it
// than in parsing. For files the reader owns (fread of a whole block waits for it to fill).
#pragma once

#include <cstddef>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string_view>

#include "hostio/line_reader.hpp"

namespace lptn::canfile {

class BlockLineReader {
 public:
  using Status = hostio::LineReader::Status;
  static constexpr std::size_t kMaxLine = hostio::LineReader::kMaxLine;
  static constexpr std::size_t kBlock = std::size_t{256} << 10;

  explicit BlockLineReader(std::FILE* f) : f_(f), buf_(new char[kBlock]) {}

  // As LineReader::next: `line` the next line without its '\n' (valid until the next call),
  // `too_long` a line of more than kMaxLine bytes skipped, `end` end of file or error.
  Status next(std::string_view& text) {
    for (;;) {
      const char* nl = static_cast<const char*>(std::memchr(buf_.get() + pos_, '\n', end_ - pos_));
      if (nl != nullptr) {
        const std::size_t n = static_cast<std::size_t>(nl - (buf_.get() + pos_));
        const char* start = buf_.get() + pos_;
        pos_ += n + 1;
        return finish(start, n, text);
      }
      // No newline in what is buffered: the line goes on in the next block (or ends the file).
      if (end_ - pos_ > kMaxLine) {
        skip_rest();
        ++number_;
        return Status::too_long;
      }
      if (eof_) {
        if (pos_ == end_) return Status::end;
        const char* start = buf_.get() + pos_;
        const std::size_t n = end_ - pos_;
        pos_ = end_;
        return finish(start, n, text);
      }
      refill();
    }
  }

  std::size_t line_number() const { return number_; }

 private:
  Status finish(const char* start, std::size_t n, std::string_view& text) {
    ++number_;
    if (n > kMaxLine) return Status::too_long;
    text = std::string_view(start, n);
    return Status::line;
  }

  // Moves the unread tail to the front and reads behind it.
  void refill() {
    const std::size_t left = end_ - pos_;
    std::memmove(buf_.get(), buf_.get() + pos_, left);
    pos_ = 0;
    end_ = left;
    const std::size_t got = std::fread(buf_.get() + end_, 1, kBlock - end_, f_);
    end_ += got;
    if (got == 0) eof_ = true;
  }

  // Drops bytes up to and including the next '\n' (or the end of the file), however far.
  void skip_rest() {
    for (;;) {
      const char* nl = static_cast<const char*>(std::memchr(buf_.get() + pos_, '\n', end_ - pos_));
      if (nl != nullptr) {
        pos_ = static_cast<std::size_t>(nl - buf_.get()) + 1;
        return;
      }
      pos_ = end_ = 0;
      if (eof_) return;
      refill();
      if (end_ == 0) return;
    }
  }

  std::FILE* f_;
  std::unique_ptr<char[]> buf_;
  std::size_t pos_ = 0, end_ = 0;
  std::size_t number_ = 0;
  bool eof_ = false;
};

}  // namespace lptn::canfile
