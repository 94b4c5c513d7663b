#include "hostio/sha256.hpp"

#include <exception>
#include <fstream>
#include <stdexcept>

#include "hostio/internal/sha256.hpp"
#include "hostio/worker_threads.hpp"

namespace lptn::hostio {

std::string sha256_hex(const void* data, std::size_t size) {
  internal::Sha256 h;
  h.update(data, size);
  return h.hex();
}

std::string sha256_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot read (missing or not readable)");
  internal::Sha256 h;
  char buf[1 << 16];
  while (in) {
    in.read(buf, sizeof buf);
    h.update(buf, static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) throw std::runtime_error(path.string() + ": read failed");
  return h.hex();
}

std::vector<std::string> sha256_files(const std::vector<std::filesystem::path>& paths, int threads) {
  std::vector<std::string> hashes(paths.size());
  std::vector<std::exception_ptr> failed(paths.size());  // a thread's exception, rethrown here in order
  parallel_for(paths.size(), threads, [&](std::size_t i) {
    try {
      hashes[i] = sha256_file(paths[i]);
    } catch (...) {
      failed[i] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : failed)
    if (e) std::rethrow_exception(e);
  return hashes;
}

}  // namespace lptn::hostio
