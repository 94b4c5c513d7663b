// TD3 in libtorch. The only translation unit of the project that includes torch's headers.
//
// Each network's parameters live in one flat float tensor; the per-layer weights are views into it
// (leaves that require grad), and their .grad are views into one flat gradient tensor. Adam and the
// soft target updates are then a handful of in-place operations on whole flat tensors, and the
// checkpoint is a few plain float arrays. Adam is written out here (same arithmetic as torch::optim::Adam
// with its defaults) so that its state is ours to save.
#include "trainer/td3/td3_agent.hpp"

#include <ATen/ATen.h>
#include <ATen/Parallel.h>
#include <c10/core/GradMode.h>

#include <dlfcn.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <mutex>
#include <optional>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "hostio/atomic_file.hpp"
#include "trainer/td3/internal/binary_io.hpp"
#include "trainer/td3/internal/replay_buffer.hpp"

namespace lptn::td3 {
namespace {

using internal::ByteReader;
using internal::ByteWriter;
using internal::FormatError;

constexpr char kMagic[8] = {'L', 'P', 'T', 'N', 'T', 'D', '3', '\0'};
constexpr std::uint32_t kVersion = 1;

// Adam's defaults in torch::optim::Adam / torch.optim.Adam.
constexpr double kBeta1 = 0.9, kBeta2 = 0.999, kAdamEps = 1e-8;

// Uniform float in [0, 1) from the top 24 bits; normal from Box-Muller on 53-bit uniforms. Written
// out (not std:: distributions) so that the numbers do not depend on the standard library.
float uniform01(std::mt19937_64& rng) { return static_cast<float>(rng() >> 40) * 0x1.0p-24f; }
double uniform01_open(std::mt19937_64& rng) { return (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53; }
void fill_normal(std::mt19937_64& rng, float* out, std::size_t n) {
  for (std::size_t i = 0; i < n; i += 2) {
    const double r = std::sqrt(-2.0 * std::log(uniform01_open(rng)));
    const double phi = 2.0 * std::numbers::pi * uniform01_open(rng);
    out[i] = static_cast<float>(r * std::cos(phi));
    if (i + 1 < n) out[i + 1] = static_cast<float>(r * std::sin(phi));
  }
}

// A network's parameters: one flat tensor, views per layer in the order the forward pass uses them.
struct FlatParams {
  at::Tensor flat;                 // all parameters
  at::Tensor grad;                 // their gradients (defined only for trained networks)
  std::vector<at::Tensor> views;   // W, b, W, b, ... (row-major, Linear's [out, in] layout)

  FlatParams() = default;
  // shapes: per tensor {rows, cols} (cols = 0 for a bias vector).
  FlatParams(const std::vector<std::pair<std::int64_t, std::int64_t>>& shapes, bool trainable) {
    std::int64_t total = 0;
    for (const auto& [r, c] : shapes) total += r * (c > 0 ? c : 1);
    flat = at::zeros({total}, at::kFloat);
    if (trainable) grad = at::zeros({total}, at::kFloat);
    std::int64_t offset = 0;
    for (const auto& [r, c] : shapes) {
      const std::int64_t n = r * (c > 0 ? c : 1);
      at::Tensor v = c > 0 ? flat.narrow(0, offset, n).view({r, c}) : flat.narrow(0, offset, n);
      if (trainable) {
        v.requires_grad_(true);
        v.mutable_grad() = c > 0 ? grad.narrow(0, offset, n).view({r, c}) : grad.narrow(0, offset, n);
      }
      views.push_back(v);
      offset += n;
    }
  }
  float* data() { return flat.data_ptr<float>(); }
  const float* data() const { return flat.data_ptr<float>(); }
  std::size_t size() const { return static_cast<std::size_t>(flat.numel()); }
};

// PyTorch's default Linear initialisation: weight and bias U(-1/sqrt(fan_in), 1/sqrt(fan_in)).
void init_linear(std::mt19937_64& rng, const at::Tensor& w, const at::Tensor& b, std::int64_t fan_in) {
  const float bound = 1.0f / std::sqrt(static_cast<float>(fan_in));
  for (const at::Tensor* t : {&w, &b}) {
    float* p = t->data_ptr<float>();
    for (std::int64_t i = 0; i < t->numel(); ++i) p[i] = (2.0f * uniform01(rng) - 1.0f) * bound;
  }
}

struct Adam {
  at::Tensor m, v, denom;
  std::int64_t step = 0;

  explicit Adam(std::int64_t n) : m(at::zeros({n}, at::kFloat)), v(at::zeros({n}, at::kFloat)), denom(at::empty({n}, at::kFloat)) {}

  void update(at::Tensor& param, const at::Tensor& grad, double lr) {
    ++step;
    m.mul_(kBeta1).add_(grad, 1.0 - kBeta1);
    v.mul_(kBeta2).addcmul_(grad, grad, 1.0 - kBeta2);
    const double bias1 = 1.0 - std::pow(kBeta1, static_cast<double>(step));
    const double bias2 = 1.0 - std::pow(kBeta2, static_cast<double>(step));
    at::sqrt_out(denom, v);
    denom.div_(std::sqrt(bias2)).add_(kAdamEps);
    param.addcdiv_(m, denom, -lr / bias1);
  }
};

std::vector<std::pair<std::int64_t, std::int64_t>> actor_shapes(std::int64_t obs, std::int64_t act, std::int64_t h) {
  return {{h, obs}, {h, 0}, {h, h}, {h, 0}, {act, h}, {act, 0}};
}
// Two critics one after the other, each: Ws, bs, Wa, ba, W2, b2, W3, b3.
constexpr std::size_t kCriticTensors = 8;
std::vector<std::pair<std::int64_t, std::int64_t>> critic_shapes(std::int64_t obs, std::int64_t act, std::int64_t h) {
  std::vector<std::pair<std::int64_t, std::int64_t>> one = {{h, obs}, {h, 0}, {h, act}, {h, 0}, {h, 2 * h}, {h, 0}, {1, h}, {1, 0}};
  auto both = one;
  both.insert(both.end(), one.begin(), one.end());
  return both;
}

// Fig. 5: obs -> Linear(h) -> ReLU -> Linear(h) -> ReLU -> Linear(act) -> tanh.
at::Tensor actor_hidden(const FlatParams& p, const at::Tensor& obs) {
  const auto& w = p.views;
  at::Tensor h = at::relu(at::linear(obs, w[0], w[1]));
  h = at::relu(at::linear(h, w[2], w[3]));
  return at::linear(h, w[4], w[5]);
}
at::Tensor actor_forward(const FlatParams& p, const at::Tensor& obs) { return at::tanh(actor_hidden(p, obs)); }

// Fig. 6: [Linear(obs -> h), Linear(act -> h)] concatenated -> ReLU -> Linear(2h -> h) -> ReLU -> Linear(h -> 1).
at::Tensor critic_forward(const FlatParams& p, std::size_t which, const at::Tensor& obs, const at::Tensor& act) {
  const at::Tensor* w = p.views.data() + which * kCriticTensors;
  at::Tensor h = at::relu(at::cat({at::linear(obs, w[0], w[1]), at::linear(act, w[2], w[3])}, 1));
  h = at::relu(at::linear(h, w[4], w[5]));
  return at::linear(h, w[6], w[7]);
}

// One thread for torch's own kernels and, unless OPENBLAS_NUM_THREADS says otherwise, for OpenBLAS:
// OpenBLAS's threaded sgemm gives (slightly) different sums than its single-threaded one, so results
// would depend on the machine's core count, and on these shared 2-core machines the second thread
// is often busy anyway. Looked up at run time: a no-op with another BLAS behind libtorch.
void use_one_thread() {
  static std::once_flag once;
  std::call_once(once, [] {
    at::set_num_threads(1);
    if (std::getenv("OPENBLAS_NUM_THREADS") != nullptr) return;
    using SetThreads = void (*)(int);
    if (void* f = ::dlsym(RTLD_DEFAULT, "openblas_set_num_threads")) reinterpret_cast<SetThreads>(f)(1);
  });
}

void check_settings(int obs_dim, int act_dim, const AgentSettings& s) {
  auto bad = [](const std::string& what) { throw std::invalid_argument("TD3 agent: " + what); };
  if (obs_dim <= 0 || act_dim <= 0) bad("observation and action sizes must be positive");
  if (s.hidden <= 0) bad("hidden must be positive");
  if (!(s.actor_lr > 0) || !(s.critic_lr > 0)) bad("learning rates must be positive");
  if (!(s.gamma >= 0 && s.gamma <= 1)) bad("gamma must be in [0, 1]");
  if (!(s.tau > 0 && s.tau <= 1)) bad("tau must be in (0, 1]");
  if (!(s.policy_noise >= 0) || !(s.noise_clip >= 0)) bad("policy_noise and noise_clip must be >= 0");
  if (s.policy_delay <= 0) bad("policy_delay must be positive");
  if (s.batch_size <= 0) bad("batch_size must be positive");
  if (s.buffer_capacity == 0) bad("buffer_capacity must be positive");
}

void put_floats(ByteWriter& out, const FlatParams& p) { out.put_array(p.data(), p.size()); }
void put_floats(ByteWriter& out, const at::Tensor& t) {
  out.put_array(t.data_ptr<float>(), static_cast<std::size_t>(t.numel()));
}
std::vector<float> get_floats(ByteReader& in, std::size_t n, const char* what) {
  std::vector<float> v(n);
  in.get_array(v.data(), n, what);
  return v;
}
void copy_into(const at::Tensor& t, const std::vector<float>& v) {
  std::memcpy(t.data_ptr<float>(), v.data(), v.size() * sizeof(float));
}

}  // namespace

struct Agent::Impl {
  int obs_dim, act_dim;
  AgentSettings settings;
  std::mt19937_64 rng;
  FlatParams actor, critic, actor_target, critic_target;
  Adam actor_adam, critic_adam;
  internal::ReplayBuffer buffer;
  std::uint64_t updates = 0;  // critic updates over the agent's life (phase of the policy delay)
  // Minibatch tensors, filled in place every step.
  at::Tensor b_obs, b_act, b_rew, b_next, b_not_done, b_noise;

  Impl(int obs, int act, const AgentSettings& s)
      : obs_dim(obs),
        act_dim(act),
        settings(s),
        rng(s.seed),
        actor(actor_shapes(obs, act, s.hidden), true),
        critic(critic_shapes(obs, act, s.hidden), true),
        actor_target(actor_shapes(obs, act, s.hidden), false),
        critic_target(critic_shapes(obs, act, s.hidden), false),
        actor_adam(actor.flat.numel()),
        critic_adam(critic.flat.numel()),
        buffer(obs, act, s.buffer_capacity) {
    const std::int64_t h = s.hidden;
    init_linear(rng, actor.views[0], actor.views[1], obs);
    init_linear(rng, actor.views[2], actor.views[3], h);
    init_linear(rng, actor.views[4], actor.views[5], h);
    for (std::size_t c = 0; c < 2; ++c) {
      const at::Tensor* w = critic.views.data() + c * kCriticTensors;
      init_linear(rng, w[0], w[1], obs);
      init_linear(rng, w[2], w[3], act);
      init_linear(rng, w[4], w[5], 2 * h);
      init_linear(rng, w[6], w[7], h);
    }
    actor_target.flat.copy_(actor.flat);
    critic_target.flat.copy_(critic.flat);
    const std::int64_t b = s.batch_size;
    b_obs = at::empty({b, obs}, at::kFloat);
    b_act = at::empty({b, act}, at::kFloat);
    b_rew = at::empty({b, 1}, at::kFloat);
    b_next = at::empty({b, obs}, at::kFloat);
    b_not_done = at::empty({b, 1}, at::kFloat);
    b_noise = at::empty({b, act}, at::kFloat);
  }

  // One TD3 step; adds the critic loss and (if the actor was updated) the actor loss.
  void step(double& critic_loss, double& actor_loss, int& actor_updates) {
    const auto batch = static_cast<std::size_t>(settings.batch_size);
    buffer.sample(rng, batch, b_obs.data_ptr<float>(), b_act.data_ptr<float>(), b_rew.data_ptr<float>(),
                  b_next.data_ptr<float>(), b_not_done.data_ptr<float>());
    fill_normal(rng, b_noise.data_ptr<float>(), batch * static_cast<std::size_t>(act_dim));

    at::Tensor y;
    {
      at::NoGradGuard no_grad;
      // Target policy smoothing, clipped double Q.
      at::Tensor noise = b_noise.mul(settings.policy_noise).clamp_(-settings.noise_clip, settings.noise_clip);
      at::Tensor next_act = actor_forward(actor_target, b_next).add_(noise).clamp_(-1.0, 1.0);
      at::Tensor q_next = at::min(critic_forward(critic_target, 0, b_next, next_act),
                                  critic_forward(critic_target, 1, b_next, next_act));
      y = q_next.mul_(b_not_done).mul_(settings.gamma).add_(b_rew);
    }

    at::Tensor loss = at::mse_loss(critic_forward(critic, 0, b_obs, b_act), y) +
                      at::mse_loss(critic_forward(critic, 1, b_obs, b_act), y);
    critic.grad.zero_();
    loss.backward();
    {
      at::NoGradGuard no_grad;
      critic_adam.update(critic.flat, critic.grad, settings.critic_lr);
    }
    critic_loss += loss.item<double>();
    ++updates;

    if (updates % static_cast<std::uint64_t>(settings.policy_delay) == 0) {
      at::Tensor a_loss = critic_forward(critic, 0, b_obs, actor_forward(actor, b_obs)).mean().neg();
      actor.grad.zero_();
      // Gradients for the actor only: the critic's weight gradients are neither needed nor computed.
      a_loss.backward({}, c10::nullopt, false, at::TensorList(actor.views));
      at::NoGradGuard no_grad;
      actor_adam.update(actor.flat, actor.grad, settings.actor_lr);
      const double tau = settings.tau;
      actor_target.flat.mul_(1.0 - tau).add_(actor.flat, tau);
      critic_target.flat.mul_(1.0 - tau).add_(critic.flat, tau);
      actor_loss += a_loss.item<double>();
      ++actor_updates;
    }
  }
};

Agent::Agent(int obs_dim, int act_dim, const AgentSettings& settings) {
  check_settings(obs_dim, act_dim, settings);
  use_one_thread();
  impl_ = std::make_unique<Impl>(obs_dim, act_dim, settings);
}

Agent::~Agent() = default;
Agent::Agent(Agent&&) noexcept = default;
Agent& Agent::operator=(Agent&&) noexcept = default;

int Agent::obs_dim() const { return impl_->obs_dim; }
int Agent::act_dim() const { return impl_->act_dim; }
const AgentSettings& Agent::settings() const { return impl_->settings; }

void Agent::act(const float* obs, std::size_t n, float* actions) const {
  if (n == 0) return;
  at::NoGradGuard no_grad;
  const auto rows = static_cast<std::int64_t>(n);
  const at::Tensor in = at::from_blob(const_cast<float*>(obs), {rows, impl_->obs_dim}, at::kFloat);
  at::Tensor out = at::from_blob(actions, {rows, impl_->act_dim}, at::kFloat);
  at::tanh_out(out, actor_hidden(impl_->actor, in));
}

void Agent::remember(const float* obs, const float* actions, const float* rewards, const float* next_obs,
                     const std::uint8_t* done, std::size_t n) {
  impl_->buffer.add(obs, actions, rewards, next_obs, done, n);
}

std::size_t Agent::buffer_size() const { return impl_->buffer.size(); }

TrainStats Agent::train(int steps) {
  TrainStats stats;
  if (steps <= 0) return stats;
  if (impl_->buffer.size() == 0) throw std::logic_error("TD3 agent: train() with an empty replay buffer");
  double critic_loss = 0, actor_loss = 0;
  int actor_updates = 0;
  for (int i = 0; i < steps; ++i) impl_->step(critic_loss, actor_loss, actor_updates);
  stats.updates = steps;
  stats.critic_loss = critic_loss / steps;
  stats.actor_loss = actor_updates > 0 ? actor_loss / actor_updates : 0.0;
  return stats;
}

ActorWeightsPlain Agent::actor_weights() const {
  const Impl& m = *impl_;
  ActorWeightsPlain w;
  w.inputs = m.obs_dim;
  w.hidden = m.settings.hidden;
  w.outputs = m.act_dim;
  std::vector<float>* dst[] = {&w.w1, &w.b1, &w.w2, &w.b2, &w.w3, &w.b3};
  for (std::size_t i = 0; i < 6; ++i) {
    const at::Tensor t = m.actor.views[i].detach().contiguous();
    const float* p = t.data_ptr<float>();
    dst[i]->assign(p, p + t.numel());
  }
  return w;
}

// File layout: magic, version, obs_dim, act_dim, hidden, buffer_capacity, then the payload, then
// a checksum of everything before it.
void Agent::save(const std::filesystem::path& file) const {
  const Impl& m = *impl_;
  ByteWriter out;
  out.put_bytes(kMagic, sizeof kMagic);
  out.put<std::uint32_t>(kVersion);
  out.put<std::int32_t>(m.obs_dim);
  out.put<std::int32_t>(m.act_dim);
  out.put<std::int32_t>(m.settings.hidden);
  out.put<std::uint64_t>(m.settings.buffer_capacity);
  out.put<std::uint64_t>(m.updates);
  std::ostringstream rng_text;
  rng_text << m.rng;
  out.put_string(rng_text.str());
  put_floats(out, m.actor);
  put_floats(out, m.critic);
  put_floats(out, m.actor_target);
  put_floats(out, m.critic_target);
  for (const Adam* a : {&m.actor_adam, &m.critic_adam}) {
    out.put<std::int64_t>(a->step);
    put_floats(out, a->m);
    put_floats(out, a->v);
  }
  m.buffer.write(out);
  const std::uint64_t sum = internal::checksum(out.data().data(), out.data().size());
  out.put(sum);
  hostio::write_file_atomically(file, out.data());
}

namespace {
// Everything an agent file holds, read and checked before anything is committed.
struct AgentImage {
  std::uint64_t updates = 0;
  std::mt19937_64 rng;
  std::vector<float> actor, critic, actor_target, critic_target;
  std::int64_t steps[2] = {0, 0};
  std::vector<float> moments[4];
  std::optional<internal::ReplayBuffer> buffer;
};

// networks_only: the networks must fit (obs_dim, act_dim, hidden); the buffer's capacity may
// differ and the optimizer's state and the buffer are not read.
template <class ImplT>
AgentImage read_agent_file(const std::filesystem::path& file, const ImplT& m, bool networks_only) {
  const auto fail = [&](const std::string& why) {
    throw std::runtime_error(file.string() + ": not a usable TD3 checkpoint: " + why);
  };
  std::string image;
  {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw std::runtime_error(file.string() + ": cannot open TD3 checkpoint");
    image.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (in.bad()) throw std::runtime_error(file.string() + ": cannot read TD3 checkpoint");
  }
  if (image.size() < sizeof kMagic || std::memcmp(image.data(), kMagic, sizeof kMagic) != 0)
    fail("wrong file type (no LPTNTD3 header)");
  if (image.size() < sizeof kMagic + sizeof(std::uint32_t) + sizeof(std::uint64_t)) fail("truncated");
  std::uint64_t stored_sum;
  std::memcpy(&stored_sum, image.data() + image.size() - sizeof stored_sum, sizeof stored_sum);
  const std::size_t body = image.size() - sizeof stored_sum;
  ByteReader in(image.data(), body);
  char magic[sizeof kMagic];
  in.get_bytes(magic, sizeof magic);
  const auto version = in.get<std::uint32_t>();
  if (version != kVersion) fail("format version " + std::to_string(version) + ", this build reads " + std::to_string(kVersion));
  if (internal::checksum(image.data(), body) != stored_sum) fail("checksum mismatch (truncated or corrupt)");
  AgentImage a;
  try {
    const auto obs = in.get<std::int32_t>();
    const auto act = in.get<std::int32_t>();
    const auto hidden = in.get<std::int32_t>();
    const auto capacity = in.get<std::uint64_t>();
    if (obs != m.obs_dim || act != m.act_dim || hidden != m.settings.hidden ||
        (!networks_only && capacity != m.settings.buffer_capacity)) {
      fail("incompatible agent: file has obs_dim " + std::to_string(obs) + ", act_dim " + std::to_string(act) +
           ", hidden " + std::to_string(hidden) + ", buffer_capacity " + std::to_string(capacity) + "; this agent " +
           std::to_string(m.obs_dim) + ", " + std::to_string(m.act_dim) + ", " + std::to_string(m.settings.hidden) +
           ", " + std::to_string(m.settings.buffer_capacity));
    }
    a.updates = in.get<std::uint64_t>();
    {
      std::istringstream text(in.get_string(1 << 16, "generator state"));
      text >> a.rng;
      if (!text) throw FormatError("generator state unreadable");
    }
    a.actor = get_floats(in, m.actor.size(), "actor");
    a.critic = get_floats(in, m.critic.size(), "critics");
    a.actor_target = get_floats(in, m.actor_target.size(), "target actor");
    a.critic_target = get_floats(in, m.critic_target.size(), "target critics");
    if (networks_only) return a;
    const std::size_t sizes[2] = {m.actor.size(), m.critic.size()};
    for (std::size_t k = 0; k < 2; ++k) {
      a.steps[k] = in.get<std::int64_t>();
      if (a.steps[k] < 0) throw FormatError("negative Adam step count");
      a.moments[2 * k] = get_floats(in, sizes[k], "Adam first moments");
      a.moments[2 * k + 1] = get_floats(in, sizes[k], "Adam second moments");
    }
    a.buffer.emplace(m.obs_dim, m.act_dim, m.settings.buffer_capacity);
    a.buffer->read(in);
    if (in.remaining() != 0) throw FormatError("unexpected data after the replay buffer");
  } catch (const FormatError& e) {
    fail(e.what());
  }
  return a;
}
}  // namespace

void Agent::load(const std::filesystem::path& file) {
  Impl& m = *impl_;
  AgentImage a = read_agent_file(file, m, false);
  // Everything read: commit.
  at::NoGradGuard no_grad;
  copy_into(m.actor.flat, a.actor);
  copy_into(m.critic.flat, a.critic);
  copy_into(m.actor_target.flat, a.actor_target);
  copy_into(m.critic_target.flat, a.critic_target);
  Adam* adams[2] = {&m.actor_adam, &m.critic_adam};
  for (std::size_t k = 0; k < 2; ++k) {
    adams[k]->step = a.steps[k];
    copy_into(adams[k]->m, a.moments[2 * k]);
    copy_into(adams[k]->v, a.moments[2 * k + 1]);
  }
  m.buffer = std::move(*a.buffer);
  m.rng = a.rng;
  m.updates = a.updates;
}

void Agent::load_networks(const std::filesystem::path& file) {
  Impl& m = *impl_;
  const AgentImage a = read_agent_file(file, m, true);
  at::NoGradGuard no_grad;
  copy_into(m.actor.flat, a.actor);
  copy_into(m.critic.flat, a.critic);
  copy_into(m.actor_target.flat, a.actor_target);
  copy_into(m.critic_target.flat, a.critic_target);
}

}  // namespace lptn::td3
