// Outputs that appear whole or not at all: written under a temporary name beside the target and
// renamed into place only when complete, so a failure or a kill never leaves a half-written file.
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>

namespace lptn::hostio {

// Every writer here names its temporary ".NAME.tmp-PID" beside NAME, and removes the temporaries
// that writers of the same NAME left when they were killed (their process is gone).

// A streamed output (a CSV or log written as it is computed) that appears whole or not at all. An
// empty path means stdout, written straight through (nothing to rename).
class AtomicFile {
 public:
  AtomicFile() = default;
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();  // removes the temporary unless committed

  // False (errno set) if the temporary cannot be created.
  bool open(const std::string& path);
  std::FILE* get() const { return f_; }
  // Closes and renames into place; false (and the temporary removed) on any write error.
  bool commit();

 private:
  std::filesystem::path path_, temp_;
  std::FILE* f_ = stdout;
};

// Writes `text` to `path` atomically (temporary file in the same directory, then rename).
void write_file_atomically(const std::filesystem::path& path, const std::string& text);

// A directory filled under a temporary name; commit() moves it to the target. If never committed
// (an error, an exception) the temporary directory is removed on destruction.
class AtomicDirectory {
 public:
  // Fails if `target` exists and is not empty, unless `replace` is set.
  AtomicDirectory(std::filesystem::path target, bool replace);
  ~AtomicDirectory();
  AtomicDirectory(const AtomicDirectory&) = delete;
  AtomicDirectory& operator=(const AtomicDirectory&) = delete;

  const std::filesystem::path& path() const { return temp_; }
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  bool replace_;
  bool committed_ = false;
};

}  // namespace lptn::hostio
