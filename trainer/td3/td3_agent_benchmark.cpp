// What one TD3 gradient step and one episode's batched action cost (paper networks, one thread).
// build/host/trainer/td3/lptn_td3_benchmark
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "trainer/td3/td3_agent.hpp"

namespace {

lptn::td3::Agent filled_agent(int act_dim) {
  lptn::td3::Agent agent(2, act_dim, lptn::td3::AgentSettings{});
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1, 1);
  const std::size_t n = 5000;
  std::vector<float> obs(n * 2), act(n * static_cast<std::size_t>(act_dim)), rew(n), next(n * 2);
  for (auto* v : {&obs, &act, &rew, &next})
    for (float& x : *v) x = u(rng);
  std::vector<std::uint8_t> done(n, 0);
  agent.remember(obs.data(), act.data(), rew.data(), next.data(), done.data(), n);
  return agent;
}

void BM_TrainStep(benchmark::State& state) {
  lptn::td3::Agent agent = filled_agent(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(agent.train(1));
}
BENCHMARK(BM_TrainStep)->Arg(6)->Unit(benchmark::kMillisecond);

void BM_ActEpisode(benchmark::State& state) {
  lptn::td3::Agent agent = filled_agent(6);
  std::vector<float> obs(9990 * 2, 0.5f), act(9990 * 6);
  for (auto _ : state) agent.act(obs.data(), 9990, act.data());
}
BENCHMARK(BM_ActEpisode)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
