#include "trainer/td3/internal/replay_buffer.hpp"

#include <algorithm>
#include <cstring>

namespace lptn::td3::internal {

ReplayBuffer::ReplayBuffer(int obs_dim, int act_dim, std::size_t capacity)
    : obs_dim_(static_cast<std::size_t>(obs_dim)), act_dim_(static_cast<std::size_t>(act_dim)), capacity_(capacity) {}

void ReplayBuffer::reserve_rows(std::size_t rows) {
  const std::size_t have = done_.size();
  if (rows <= have) return;
  // Geometric growth up to the capacity, so a small run never allocates the full ring.
  const std::size_t grown = std::min(capacity_, std::max({rows, have * 2, std::size_t{1024}}));
  obs_.resize(grown * obs_dim_);
  next_obs_.resize(grown * obs_dim_);
  act_.resize(grown * act_dim_);
  rew_.resize(grown);
  done_.resize(grown);
}

void ReplayBuffer::add(const float* obs, const float* actions, const float* rewards, const float* next_obs,
                       const std::uint8_t* done, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    if (head_ >= done_.size()) reserve_rows(head_ + 1);
    std::memcpy(&obs_[head_ * obs_dim_], obs + i * obs_dim_, obs_dim_ * sizeof(float));
    std::memcpy(&next_obs_[head_ * obs_dim_], next_obs + i * obs_dim_, obs_dim_ * sizeof(float));
    std::memcpy(&act_[head_ * act_dim_], actions + i * act_dim_, act_dim_ * sizeof(float));
    rew_[head_] = rewards[i];
    done_[head_] = done[i] != 0 ? 1 : 0;
    head_ = head_ + 1 == capacity_ ? 0 : head_ + 1;
    size_ = std::min(size_ + 1, capacity_);
  }
}

void ReplayBuffer::sample(std::mt19937_64& rng, std::size_t batch, float* obs, float* actions, float* rewards,
                          float* next_obs, float* not_done) const {
  for (std::size_t b = 0; b < batch; ++b) {
    const std::size_t k = static_cast<std::size_t>(rng() % size_);  // bias ~ size / 2^64: none to speak of
    std::memcpy(obs + b * obs_dim_, &obs_[k * obs_dim_], obs_dim_ * sizeof(float));
    std::memcpy(next_obs + b * obs_dim_, &next_obs_[k * obs_dim_], obs_dim_ * sizeof(float));
    std::memcpy(actions + b * act_dim_, &act_[k * act_dim_], act_dim_ * sizeof(float));
    rewards[b] = rew_[k];
    not_done[b] = done_[k] != 0 ? 0.f : 1.f;
  }
}

void ReplayBuffer::write(ByteWriter& out) const {
  // Rows 0..size-1 are the filled ones (the ring fills from row 0 and only wraps once full).
  out.put<std::uint64_t>(size_);
  out.put<std::uint64_t>(head_);
  out.put_array(obs_.data(), size_ * obs_dim_);
  out.put_array(act_.data(), size_ * act_dim_);
  out.put_array(rew_.data(), size_);
  out.put_array(next_obs_.data(), size_ * obs_dim_);
  out.put_array(done_.data(), size_);
}

void ReplayBuffer::read(ByteReader& in) {
  const auto size = in.get<std::uint64_t>();
  const auto head = in.get<std::uint64_t>();
  if (size > capacity_ || head >= std::max<std::uint64_t>(capacity_, 1) || (size < capacity_ && head != size))
    throw FormatError("replay buffer: inconsistent size");
  ReplayBuffer fresh(static_cast<int>(obs_dim_), static_cast<int>(act_dim_), capacity_);
  fresh.reserve_rows(static_cast<std::size_t>(size));
  fresh.size_ = static_cast<std::size_t>(size);
  fresh.head_ = static_cast<std::size_t>(head);
  in.get_array(fresh.obs_.data(), fresh.size_ * obs_dim_, "replay buffer observations");
  in.get_array(fresh.act_.data(), fresh.size_ * act_dim_, "replay buffer actions");
  in.get_array(fresh.rew_.data(), fresh.size_, "replay buffer rewards");
  in.get_array(fresh.next_obs_.data(), fresh.size_ * obs_dim_, "replay buffer next observations");
  in.get_array(fresh.done_.data(), fresh.size_, "replay buffer done flags");
  *this = std::move(fresh);
}

}  // namespace lptn::td3::internal
