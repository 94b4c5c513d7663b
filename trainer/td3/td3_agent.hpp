// TD3 (Fujimoto, van Hoof, Meger 2018: twin delayed deep deterministic policy gradient) in libtorch,
// with the networks of the paper's figures 5 and 6. libtorch stays behind this header (pimpl): the
// rest of the project includes it without paying for torch's headers.
//
// Everything random (initial weights, minibatch indices, target policy smoothing noise) comes from
// the agent's own std::mt19937_64 seeded with AgentSettings::seed, so two agents with the same seed
// and the same calls give bit-identical results, and a checkpoint carries the generator's state.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

namespace lptn::td3 {

struct AgentSettings {
  int hidden = 256;             // paper figs 5/6
  double actor_lr = 1e-3;       // TD3 authors' values (Fujimoto et al. 2018) unless noted
  double critic_lr = 1e-3;
  double gamma = 0.99;          // discount
  double tau = 0.005;           // soft target update
  double policy_noise = 0.2;    // target policy smoothing noise (std, in action units [-1,1])
  double noise_clip = 0.5;
  int policy_delay = 2;         // actor and targets updated every 2 critic updates
  int batch_size = 256;
  std::size_t buffer_capacity = 1'000'000;
  std::uint64_t seed = 1;
};

struct TrainStats {
  double critic_loss = 0;  // mean over the steps of MSE(Q1, y) + MSE(Q2, y)
  double actor_loss = 0;   // mean over the actor updates of -mean Q1(s, pi(s)); 0 if none happened
  int updates = 0;         // gradient steps done (critic updates)
};

struct ActorWeightsPlain {  // for export: row-major float copies of the actor's three Linear layers
  int inputs = 0, hidden = 0, outputs = 0;
  std::vector<float> w1, b1, w2, b2, w3, b3;  // hidden x inputs, hidden, hidden x hidden, hidden,
                                              // outputs x hidden, outputs
};

class Agent {
 public:
  // Throws std::invalid_argument on non-positive sizes or settings out of range.
  // Sets libtorch to one intra-op thread (faster on these 2-core machines).
  Agent(int obs_dim, int act_dim, const AgentSettings& settings);
  ~Agent();
  Agent(Agent&&) noexcept;
  Agent& operator=(Agent&&) noexcept;

  int obs_dim() const;
  int act_dim() const;
  const AgentSettings& settings() const;

  // Deterministic policy (tanh outputs in [-1,1]) for n observations, row-major n x obs_dim -> n x act_dim.
  // One forward pass for the whole batch.
  void act(const float* obs, std::size_t n, float* actions) const;

  // Stores n transitions (row-major arrays). done[i] != 0 ends the episode at transition i (no bootstrap).
  // When the buffer is full the oldest transitions are overwritten.
  void remember(const float* obs, const float* actions, const float* rewards, const float* next_obs,
                const std::uint8_t* done, std::size_t n);
  std::size_t buffer_size() const;

  // `steps` TD3 gradient steps, each on a minibatch of batch_size transitions drawn uniformly (with
  // replacement) from the buffer: critic update towards r + gamma (1 - done) min(Q1', Q2')(s', a~),
  // a~ = clip(pi'(s') + clip(N(0, policy_noise), +-noise_clip), +-1); every policy_delay-th step
  // (counted over the agent's life, not per call) the actor update (maximize Q1(s, pi(s))) and the
  // soft updates of the three target networks. Throws std::logic_error if the buffer is empty.
  TrainStats train(int steps);

  // Everything needed to continue bit-for-bit: networks, targets, Adam states, replay buffer, the
  // agent's RNG state, update counter. Written atomically (temp file + rename in the same directory).
  // Binary, little-endian host layout, with a checksum.
  void save(const std::filesystem::path& file) const;
  // Throws std::runtime_error naming the file on an unreadable, corrupt, truncated or incompatible
  // file (obs_dim, act_dim, hidden and buffer_capacity must match this agent). The learning
  // hyperparameters (rates, gamma, tau, noise, delay, batch size) stay this agent's own settings.
  // On a throw the agent is unchanged.
  void load(const std::filesystem::path& file);
  // A warm start: the networks (actor, critics and their targets) of an agent file whose
  // obs_dim, act_dim and hidden match this agent's; this agent's optimizer state, replay buffer,
  // generator and update count stay as they are. Throws as load() does; the agent is then unchanged.
  void load_networks(const std::filesystem::path& file);

  ActorWeightsPlain actor_weights() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lptn::td3
