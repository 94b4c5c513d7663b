// A streamed output that appears whole or not at all: written to FILE.part, renamed over FILE on
// commit(), removed if never committed. An empty path means stdout (nothing to rename).
#pragma once

#include <cstdio>
#include <string>

namespace lptn::fw {

class AtomicFile {
 public:
  AtomicFile() = default;
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile() {
    if (f_ && f_ != stdout) {
      std::fclose(f_);
      std::remove(temp_.c_str());
    }
  }

  bool open(const std::string& path) {
    if (path.empty()) return true;
    path_ = path;
    temp_ = path + ".part";
    f_ = std::fopen(temp_.c_str(), "w");
    return f_ != nullptr;
  }
  std::FILE* get() const { return f_; }

  bool commit() {
    if (f_ == stdout) return std::fflush(stdout) == 0;
    const bool written = !std::ferror(f_);
    const bool closed = std::fclose(f_) == 0;
    f_ = nullptr;
    if (written && closed && std::rename(temp_.c_str(), path_.c_str()) == 0) return true;
    std::remove(temp_.c_str());
    return false;
  }

 private:
  std::string path_, temp_;
  std::FILE* f_ = stdout;
};

}  // namespace lptn::fw
