// The replay buffer: a ring of compact rows (float observation, action, reward, next observation;
// uint8 done), grown on demand up to its capacity. No torch here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "trainer/td3/internal/binary_io.hpp"

namespace lptn::td3::internal {

class ReplayBuffer {
 public:
  ReplayBuffer(int obs_dim, int act_dim, std::size_t capacity);

  void add(const float* obs, const float* actions, const float* rewards, const float* next_obs,
           const std::uint8_t* done, std::size_t n);
  std::size_t size() const { return size_; }
  std::size_t capacity() const { return capacity_; }

  // Draws `batch` rows uniformly with replacement (indices from `rng`) into the given arrays:
  // obs batch x obs_dim, actions batch x act_dim, rewards batch, next_obs batch x obs_dim and
  // not_done batch (1 - done, as float). Precondition: size() > 0.
  void sample(std::mt19937_64& rng, std::size_t batch, float* obs, float* actions, float* rewards,
              float* next_obs, float* not_done) const;

  void write(ByteWriter& out) const;
  // Reads what write() wrote for a buffer of the same dimensions and capacity (the caller checked them).
  void read(ByteReader& in);

 private:
  void reserve_rows(std::size_t rows);

  std::size_t obs_dim_, act_dim_, capacity_;
  std::size_t size_ = 0;  // rows held
  std::size_t head_ = 0;  // next row to write
  std::vector<float> obs_, act_, rew_, next_obs_;
  std::vector<std::uint8_t> done_;
};

}  // namespace lptn::td3::internal
