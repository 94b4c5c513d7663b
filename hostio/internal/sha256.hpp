// SHA-256 (FIPS 180-4), small and dependency-free: calibration files record the hash of every data
// file they were fitted to, so that a result can be traced to the exact bytes.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace lptn::hostio::internal {

// Incremental: update() any number of times, then hex() once.
class Sha256 {
 public:
  Sha256();
  void update(const void* data, std::size_t size);
  std::string hex();  // finishes the hash; the object is spent afterwards

 private:
  void block(const std::uint8_t* p);

  std::array<std::uint32_t, 8> h_;
  std::array<std::uint8_t, 64> buffer_{};
  std::size_t buffered_ = 0;
  std::uint64_t total_bytes_ = 0;
};

}  // namespace lptn::hostio::internal
