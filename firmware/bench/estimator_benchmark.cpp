// The estimator's cost per step: one tick with that tick's frames received (as the daemon does it
// every 100 ms), with the calibration's constant parameters and with its TD3 actor scheduling
// them, in double (Linux controller) and float (Cortex-M); and the allocations per step, counted
// by a replaced operator new and malloc (the no-heap test asserts 0; here it is reported).
//
//   build/host/firmware/bench/lptn_estimator_benchmark
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>
#include <new>
#include <vector>

#include LPTN_BENCH_CALIBRATION_HEADER
#include "lptn_testing/converter.hpp"
#include "lptn/firmware/estimator.hpp"
#include "lptn/firmware/exported_calibration.hpp"
#include "lptn/firmware/output_frames.hpp"

extern "C" void* __libc_malloc(std::size_t);
extern "C" void __libc_free(void*);
namespace {
long g_allocations = 0;
}
extern "C" void* malloc(std::size_t n) {
  ++g_allocations;
  return __libc_malloc(n);
}
extern "C" void free(void* p) { __libc_free(p); }
void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = __libc_malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { __libc_free(p); }
void operator delete(void* p, std::size_t) noexcept { __libc_free(p); }

namespace {

using namespace lptn;
using namespace lptn::fw;

struct Timed {
  TimeUs t;
  CanFrame f;
};

// An hour of the test duty's frames, made once.
const std::vector<Timed>& frames() {
  static const std::vector<Timed> all = [] {
    std::vector<Timed> v;
    fw::testing::Converter c;
    fw::testing::Plant plant(fw::testing::true_params(), 30.0);
    for (TimeUs t = 0; t < 3600 * kUsPerS; t += kUsPerS / 10) {
      fw::testing::DriveState s = fw::testing::drive_at(static_cast<double>(t) / kUsPerS);
      s.stator_c = plant.sensor_reading();
      c.frames_at(t, s, [&](const CanFrame& f) { v.push_back({t, f}); });
      plant.step(s);
    }
    return v;
  }();
  return all;
}

template <class T>
void BM_EstimatorStep(benchmark::State& state) {
  EstimatorConfig<T> config = config_from_exported_header<T>();
  config.use_actor = state.range(0) != 0;
  if (config.use_actor && !config.actor.actor) {
    state.SkipWithError("the calibration header has no actor");
    return;
  }
  auto estimator = std::make_unique<Estimator<T>>(config);
  const std::vector<Timed>& all = frames();
  std::size_t at = 0;
  TimeUs tick = 0;
  CanFrame out[kMaxOutputFrames];
  long steps = 0, start_up = 0;  // start_up: allocations of the estimator's own re-creation
  const long allocations_before = g_allocations;
  for (auto _ : state) {
    if (at >= all.size()) {  // start the hour again: a new estimator (start-up, not a step)
      at = 0;
      tick = 0;
      state.PauseTiming();
      const long before = g_allocations;
      estimator = std::make_unique<Estimator<T>>(config);
      start_up += g_allocations - before;
      state.ResumeTiming();
    }
    for (; at < all.size() && all[at].t <= tick; ++at) estimator->receive(all[at].f, all[at].t);
    const EstimatorOutput<T>& o = estimator->tick(tick);
    benchmark::DoNotOptimize(pack_outputs(o, out));
    tick += kUsPerS / 10;
    ++steps;
  }
  state.counters["allocs_per_step"] =
      benchmark::Counter(static_cast<double>(g_allocations - allocations_before - start_up) / static_cast<double>(steps));
  state.counters["actor"] = config.use_actor ? 1 : 0;
}

BENCHMARK_TEMPLATE(BM_EstimatorStep, double)->ArgName("actor")->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_EstimatorStep, float)->ArgName("actor")->Arg(0)->Arg(1);

}  // namespace

BENCHMARK_MAIN();
