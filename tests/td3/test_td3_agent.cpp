// The TD3 agent: it learns (a contextual bandit), it is deterministic, its checkpoints continue
// bit-for-bit, and the freestanding actor (common/lptn/actor.hpp) reproduces its policy.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include "lptn/actor.hpp"
#include "trainer/td3/td3_agent.hpp"

namespace {
namespace fs = std::filesystem;
using lptn::td3::Agent;
using lptn::td3::AgentSettings;
using lptn::td3::TrainStats;
using Clock = std::chrono::steady_clock;

constexpr int kObs = 2, kAct = 3;

std::vector<float> uniform(std::mt19937& rng, std::size_t n, float lo, float hi) {
  std::uniform_real_distribution<float> u(lo, hi);
  std::vector<float> v(n);
  for (auto& x : v) x = u(rng);
  return v;
}

// The bandit: observation x in [-1,1]^2, best action target(x) = 0.7 tanh(A x + c) (off-centre, so
// the untrained policy, which outputs about 0, is far from it), reward -sum_j |a_j - target_j(x)|.
struct Bandit {
  static constexpr float A[kAct][kObs] = {{1.5f, -1.0f}, {0.5f, 2.0f}, {-1.2f, 0.8f}};
  static constexpr float c[kAct] = {0.8f, -0.7f, 0.6f};
  static float reward(const float* x, const float* a) {
    float r = 0;
    for (int j = 0; j < kAct; ++j) r -= std::fabs(a[j] - 0.7f * std::tanh(A[j][0] * x[0] + A[j][1] * x[1] + c[j]));
    return r;
  }
  static double mean_reward(const std::vector<float>& obs, const std::vector<float>& act) {
    double sum = 0;
    const std::size_t n = obs.size() / kObs;
    for (std::size_t i = 0; i < n; ++i) sum += reward(&obs[i * kObs], &act[i * kAct]);
    return sum / static_cast<double>(n);
  }
};

// Collects n transitions with the policy plus Gaussian exploration noise (or uniform random actions).
void collect(Agent& agent, std::mt19937& rng, std::size_t n, float noise, bool random_actions) {
  auto obs = uniform(rng, n * kObs, -1.f, 1.f);
  std::vector<float> act(n * kAct);
  if (random_actions) {
    act = uniform(rng, n * kAct, -1.f, 1.f);
  } else {
    agent.act(obs.data(), n, act.data());
    std::normal_distribution<float> g(0.f, noise);
    for (auto& a : act) a = std::clamp(a + g(rng), -1.f, 1.f);
  }
  std::vector<float> rew(n);
  for (std::size_t i = 0; i < n; ++i) rew[i] = Bandit::reward(&obs[i * kObs], &act[i * kAct]);
  const std::vector<std::uint8_t> done(n, 1);
  agent.remember(obs.data(), act.data(), rew.data(), obs.data(), done.data(), n);
}

double policy_reward(const Agent& agent, const std::vector<float>& obs) {
  std::vector<float> act(obs.size() / kObs * kAct);
  agent.act(obs.data(), obs.size() / kObs, act.data());
  return Bandit::mean_reward(obs, act);
}

// A small agent for the tests that only need the mechanics (fast).
AgentSettings small_settings(std::uint64_t seed) {
  AgentSettings s;
  s.hidden = 32;
  s.batch_size = 64;
  s.seed = seed;
  return s;
}

std::vector<float> actions_of(const Agent& agent, const std::vector<float>& obs) {
  std::vector<float> act(obs.size() / static_cast<std::size_t>(agent.obs_dim()) * static_cast<std::size_t>(agent.act_dim()));
  agent.act(obs.data(), obs.size() / static_cast<std::size_t>(agent.obs_dim()), act.data());
  return act;
}

// A file in a directory of its own for the running test.
fs::path temp_file(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() /
                       ("lptn_td3_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
                        "_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

TEST(Td3Agent, LearnsAContextualBandit) {
  const AgentSettings s;  // the paper's networks (hidden 256) and the TD3 authors' settings
  Agent agent(kObs, kAct, s);
  std::mt19937 rng(11);
  const auto test_obs = uniform(rng, 2000 * kObs, -1.f, 1.f);
  const double untrained = policy_reward(agent, test_obs);
  const double random = Bandit::mean_reward(test_obs, uniform(rng, 2000 * kAct, -1.f, 1.f));

  const auto t0 = Clock::now();
  collect(agent, rng, 1000, 0, true);
  TrainStats last;
  for (int round = 0; round < 12; ++round) {
    collect(agent, rng, 100, 0.2f, false);
    last = agent.train(50);
  }
  const double trained = policy_reward(agent, test_obs);
  std::printf("mean reward over 2000 fresh observations: random actions %.3f, untrained policy %.3f, "
              "trained policy %.3f (600 steps, %.1f s; last critic loss %.4f)\n",
              random, untrained, trained, std::chrono::duration<double>(Clock::now() - t0).count(), last.critic_loss);
  EXPECT_EQ(agent.buffer_size(), 2200u);
  EXPECT_EQ(last.updates, 50);
  // Random actions are ~1.9 off in sum, the untrained policy ~1.4: the trained one must be within
  // 0.05 per action component on average.
  EXPECT_LT(untrained, -1.0);
  EXPECT_LT(random, -1.0);
  EXPECT_GT(trained, -0.15);
}

// Feeds two agents the same transitions and training.
void same_calls(Agent& a, Agent& b, std::uint32_t data_seed, std::size_t n, int steps) {
  std::mt19937 ra(data_seed), rb(data_seed);
  collect(a, ra, n, 0.3f, false);
  collect(b, rb, n, 0.3f, false);
  const auto sa = a.train(steps);
  const auto sb = b.train(steps);
  EXPECT_EQ(sa.critic_loss, sb.critic_loss);
  EXPECT_EQ(sa.actor_loss, sb.actor_loss);
}

TEST(Td3Agent, SameSeedAndCallsGiveIdenticalResults) {
  Agent a(kObs, kAct, small_settings(5)), b(kObs, kAct, small_settings(5)), other(kObs, kAct, small_settings(6));
  std::mt19937 rng(1);
  const auto probe = uniform(rng, 200 * kObs, -1.f, 1.f);
  EXPECT_EQ(actions_of(a, probe), actions_of(b, probe));
  EXPECT_NE(actions_of(a, probe), actions_of(other, probe));  // the seed does something
  same_calls(a, b, 21, 500, 41);
  same_calls(a, b, 22, 100, 40);
  EXPECT_EQ(actions_of(a, probe), actions_of(b, probe));
  const auto w = a.actor_weights();
  EXPECT_EQ(w.w2, b.actor_weights().w2);
  const Agent moved = std::move(b);
  EXPECT_EQ(actions_of(a, probe), actions_of(moved, probe));
}

// Reward 1 on every transition: Q is 1 where every transition ends an episode, and
// 1 / (1 - gamma) = 2 where none does. The actor loss is -mean Q1(s, pi(s)).
TEST(Td3Agent, DoneStopsTheBootstrap) {
  for (const std::uint8_t done_flag : {std::uint8_t{1}, std::uint8_t{0}}) {
    AgentSettings s = small_settings(3);
    s.gamma = 0.5;
    s.tau = 0.1;
    Agent agent(kObs, kAct, s);
    std::mt19937 rng(8);
    const std::size_t n = 500;
    const auto obs = uniform(rng, n * kObs, -1.f, 1.f);
    const auto next = uniform(rng, n * kObs, -1.f, 1.f);
    const auto act = uniform(rng, n * kAct, -1.f, 1.f);
    const std::vector<float> rew(n, 1.f);
    const std::vector<std::uint8_t> done(n, done_flag);
    agent.remember(obs.data(), act.data(), rew.data(), next.data(), done.data(), n);
    agent.train(600);
    const double q = -agent.train(50).actor_loss;
    std::printf("done = %d: Q = %.3f\n", done_flag, q);
    EXPECT_NEAR(q, done_flag ? 1.0 : 2.0, 0.15);
  }
}

TEST(Td3Agent, CheckpointContinuesBitForBit) {
  Agent original(kObs, kAct, small_settings(5));
  std::mt19937 rng(2);
  collect(original, rng, 700, 0.3f, false);
  original.train(41);  // odd: the policy-delay phase must survive the checkpoint too
  const fs::path file = temp_file("agent.td3");
  original.save(file);
  EXPECT_EQ(std::distance(fs::directory_iterator(file.parent_path()), fs::directory_iterator()), 1);  // no temp file left

  Agent loaded(kObs, kAct, small_settings(99));  // another seed: everything must come from the file
  loaded.load(file);
  EXPECT_EQ(loaded.buffer_size(), original.buffer_size());
  const auto probe = uniform(rng, 300 * kObs, -3.f, 3.f);
  EXPECT_EQ(actions_of(original, probe), actions_of(loaded, probe));

  // Continuing both the same way: identical only if Adam's moments and step counts, the target
  // networks, the buffer, the RNG and the update counter all came back.
  same_calls(original, loaded, 23, 300, 33);
  same_calls(original, loaded, 24, 50, 10);
  EXPECT_EQ(actions_of(original, probe), actions_of(loaded, probe));
  EXPECT_EQ(original.actor_weights().w1, loaded.actor_weights().w1);

  // The same calls on a fresh agent with the original seed but without the checkpoint do not get there.
  Agent fresh(kObs, kAct, small_settings(5));
  std::mt19937 r23(23), r24(24);
  collect(fresh, r23, 300, 0.3f, false);
  fresh.train(33);
  collect(fresh, r24, 50, 0.3f, false);
  fresh.train(10);
  EXPECT_NE(actions_of(fresh, probe), actions_of(original, probe));
  fs::remove_all(file.parent_path());
}

TEST(Td3Agent, BadCheckpointsThrowNamingTheFile) {
  Agent agent(kObs, kAct, small_settings(5));
  std::mt19937 rng(3);
  collect(agent, rng, 300, 0.3f, false);
  agent.train(5);
  const fs::path good = temp_file("good.td3");
  agent.save(good);
  std::string image;
  {
    std::ifstream in(good, std::ios::binary);
    image.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  ASSERT_GT(image.size(), 1000u);

  const auto probe = uniform(rng, 50 * kObs, -1.f, 1.f);
  Agent target(kObs, kAct, small_settings(7));
  const auto before = actions_of(target, probe);
  auto expect_throw_naming = [&](const fs::path& file, const std::string& why) {
    try {
      target.load(file);
      ADD_FAILURE() << why << ": no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << why << ": " << e.what();
      std::printf("%s: %s\n", why.c_str(), e.what());
    }
    EXPECT_EQ(actions_of(target, probe), before) << why << ": a failed load changed the agent";
  };
  auto write = [&](const std::string& name, const std::string& bytes) {
    const fs::path f = temp_file(name);
    std::ofstream(f, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return f;
  };
  expect_throw_naming(write("truncated.td3", image.substr(0, image.size() / 2)), "truncated");
  expect_throw_naming(write("short.td3", image.substr(0, 10)), "short");
  expect_throw_naming(write("empty.td3", ""), "empty");
  std::string flipped = image;
  flipped[image.size() / 3] = static_cast<char>(flipped[image.size() / 3] ^ 0x10);
  expect_throw_naming(write("flipped.td3", flipped), "one bit flipped");
  expect_throw_naming(write("text.td3", "hello, world\n"), "not a checkpoint");
  expect_throw_naming(temp_file("missing.td3"), "missing");
  Agent wider(kObs, kAct + 1, small_settings(5));
  const fs::path other = temp_file("other.td3");
  wider.save(other);
  expect_throw_naming(other, "other action size");

  target.load(good);  // and the good one still loads
  EXPECT_EQ(actions_of(target, probe), actions_of(agent, probe));
  fs::remove_all(good.parent_path());
}

TEST(Td3Agent, FreestandingActorReproducesThePolicy) {
  const AgentSettings s;  // hidden 256, as exported
  Agent agent(kObs, kAct, s);
  std::mt19937 rng(4);
  collect(agent, rng, 2000, 0, true);
  agent.train(20);  // weights away from their initial values
  const auto w = agent.actor_weights();
  ASSERT_EQ(w.inputs, kObs);
  ASSERT_EQ(w.hidden, 256);
  ASSERT_EQ(w.outputs, kAct);
  ASSERT_EQ(w.w1.size(), 256u * kObs);
  ASSERT_EQ(w.w2.size(), 256u * 256u);
  ASSERT_EQ(w.w3.size(), static_cast<std::size_t>(kAct) * 256u);
  const lptn::ActorView view{w.inputs, w.hidden, w.outputs, w.w1.data(), w.b1.data(), w.w2.data(),
                             w.b2.data(), w.w3.data(), w.b3.data()};
  double worst = 0;
  int unsaturated = 0;
  for (const float scale : {1.f, 10.f, 1000.f, 1e6f}) {
    const auto obs = uniform(rng, 3000 * kObs, -scale, scale);
    const auto expected = actions_of(agent, obs);
    for (std::size_t i = 0; i < 3000; ++i) {
      float a[kAct];
      ASSERT_TRUE(lptn::actor_forward(view, &obs[i * kObs], a));
      for (int j = 0; j < kAct; ++j) {
        const double err = std::fabs(static_cast<double>(a[j]) - expected[i * kAct + static_cast<std::size_t>(j)]);
        worst = std::max(worst, err);
        ASSERT_LE(err, 1e-5) << "scale " << scale << ", observation " << i << ", action " << j;
        unsaturated += std::fabs(a[j]) < 0.99f;
      }
    }
  }
  std::printf("largest difference from libtorch: %.3g (%d unsaturated outputs)\n", worst, unsaturated);
  EXPECT_GT(unsaturated, 3000);  // the comparison is not only of saturated outputs

  // Sizes beyond the compile-time bounds: false, nothing written.
  float a[kAct] = {7.f, 7.f, 7.f};
  const float x[kObs] = {0.1f, 0.2f};
  EXPECT_FALSE((lptn::actor_forward<128, 32>(view, x, a)));
  EXPECT_FALSE((lptn::actor_forward<256, 2>(view, x, a)));
  EXPECT_EQ(a[0], 7.f);
  EXPECT_EQ(a[2], 7.f);
}

TEST(Td3Agent, RejectsBadSettingsAndEmptyBuffer) {
  AgentSettings s = small_settings(1);
  EXPECT_THROW(Agent(0, kAct, s), std::invalid_argument);
  s.policy_delay = 0;
  EXPECT_THROW(Agent(kObs, kAct, s), std::invalid_argument);
  Agent agent(kObs, kAct, small_settings(1));
  EXPECT_THROW(agent.train(1), std::logic_error);
  EXPECT_EQ(agent.train(0).updates, 0);
}

}  // namespace
