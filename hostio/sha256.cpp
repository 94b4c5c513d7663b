#include "hostio/sha256.hpp"

#include <fstream>
#include <stdexcept>

#include "hostio/internal/sha256.hpp"

namespace lptn {

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

}  // namespace lptn
