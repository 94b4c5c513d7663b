#include "hostio/atomic_file.hpp"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace lptn::hostio {
namespace fs = std::filesystem;

namespace {
std::string temp_prefix_for(const fs::path& target) {
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string chains.
  std::string name(".");
  name.append(target.filename().string()).append(".tmp-");
  return name;
}

fs::path temp_name_for(const fs::path& target) {
  fs::path dir = target.parent_path();
  if (dir.empty()) dir = ".";
  return dir / (temp_prefix_for(target) + std::to_string(::getpid()));
}

// A process killed outright (SIGKILL, power loss) leaves its temporary behind; the next writer of
// the same target removes those whose process is gone, so that kills do not pile them up.
void remove_stale_temporaries(const fs::path& target) {
  fs::path dir = target.parent_path();
  if (dir.empty()) dir = ".";
  const std::string prefix = temp_prefix_for(target);
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    std::size_t used = 0;
    long pid = 0;
    try {
      pid = std::stol(name.substr(prefix.size()), &used);
    } catch (const std::exception&) {
      continue;
    }
    const std::string rest = name.substr(prefix.size() + used);
    if (pid <= 0 || pid == ::getpid() || !(rest.empty() || rest == ".old")) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to judge
    std::error_code ignored;
    fs::remove_all(entry.path(), ignored);
  }
}
}  // namespace

AtomicFile::~AtomicFile() {
  if (f_ && f_ != stdout) {
    std::fclose(f_);
    std::error_code ignored;
    fs::remove(temp_, ignored);
  }
}

bool AtomicFile::open(const std::string& path) {
  if (path.empty()) return true;
  path_ = path;
  remove_stale_temporaries(path_);
  temp_ = temp_name_for(path_);
  f_ = std::fopen(temp_.c_str(), "w");
  return f_ != nullptr;
}

bool AtomicFile::commit() {
  if (f_ == stdout) return std::fflush(stdout) == 0;
  const bool written = !std::ferror(f_);
  const bool closed = std::fclose(f_) == 0;
  f_ = nullptr;
  std::error_code ec;
  if (written && closed) {
    fs::rename(temp_, path_, ec);
    if (!ec) return true;
  }
  fs::remove(temp_, ec);
  return false;
}

void write_file_atomically(const fs::path& path, const std::string& text) {
  remove_stale_temporaries(path);
  const fs::path temp = temp_name_for(path);
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path.string() + ": cannot write (directory missing or not writable)");
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.flush();
    if (!out) {
      std::error_code ignored;
      fs::remove(temp, ignored);
      throw std::runtime_error(path.string() + ": write failed (disk full?)");
    }
  }
  std::error_code ec;
  fs::rename(temp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    throw std::runtime_error(path.string() + ": cannot replace: " + ec.message());
  }
}

AtomicDirectory::AtomicDirectory(fs::path target, bool replace) : target_(std::move(target)), replace_(replace) {
  if (target_.filename().empty()) target_ = target_.parent_path();  // "out/" -> "out"
  if (fs::exists(target_) && !(fs::is_directory(target_) && fs::is_empty(target_)) && !replace_)
    throw std::invalid_argument(target_.string() + ": exists and is not empty (use --force to replace it)");
  remove_stale_temporaries(target_);
  temp_ = temp_name_for(target_);
  fs::remove_all(temp_);
  fs::create_directories(temp_);
}

AtomicDirectory::~AtomicDirectory() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove_all(temp_, ignored);
  }
}

void AtomicDirectory::commit() {
  if (fs::exists(target_)) {
    // Move the old one aside first so that the target is never missing and never half-replaced
    // for longer than two renames.
    const fs::path old = temp_name_for(target_).string() + ".old";
    fs::remove_all(old);
    fs::rename(target_, old);
    fs::rename(temp_, target_);
    fs::remove_all(old);
  } else {
    fs::rename(temp_, target_);
  }
  committed_ = true;
}

}  // namespace lptn::hostio
