// The firmware core never allocates after start-up (Eigen's nomalloc test, done for the whole
// process): every operator new and malloc is counted, and a whole replayed driving cycle through
// the estimator (frames in, ticks, output frames packed) must count none. A plain program with
// its own main, since GoogleTest allocates; ctest reads the exit code.
//
// EIGEN_RUNTIME_NO_MALLOC would make Eigen assert on a heap allocation; the firmware does not use
// Eigen at all, which the #error below keeps true.
#define EIGEN_RUNTIME_NO_MALLOC
#include <cstdio>
#include <cstdlib>
#include <new>
#include <vector>

#include "lptn_testing/converter.hpp"
#include "lptn/firmware/estimator.hpp"
#include "lptn/firmware/output_frames.hpp"

#ifdef EIGEN_WORLD_VERSION
#error "the firmware core must not pull in Eigen"
#endif

extern "C" void* __libc_malloc(std::size_t);
extern "C" void* __libc_calloc(std::size_t, std::size_t);
extern "C" void* __libc_realloc(void*, std::size_t);
extern "C" void __libc_free(void*);

namespace {
bool counting = false;
long allocations = 0;
void note() {
  if (counting) ++allocations;
}
}  // namespace

extern "C" void* malloc(std::size_t n) {
  note();
  return __libc_malloc(n);
}
extern "C" void* calloc(std::size_t n, std::size_t size) {
  note();
  return __libc_calloc(n, size);
}
extern "C" void* realloc(void* p, std::size_t n) {
  note();
  return __libc_realloc(p, n);
}
extern "C" void free(void* p) { __libc_free(p); }

void* operator new(std::size_t n) {
  note();
  if (void* p = __libc_malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  note();
  return __libc_malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t& t) noexcept { return operator new(n, t); }
void operator delete(void* p) noexcept { __libc_free(p); }
void operator delete[](void* p) noexcept { __libc_free(p); }
void operator delete(void* p, std::size_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::size_t) noexcept { __libc_free(p); }

int main() {
  using namespace lptn;
  using namespace lptn::fw;
  // Start-up: may allocate (here it does not need to, but it is outside the promise).
  const auto config = default_config<double>(fw::testing::example_motor(), (EffectSet{1} << kNumEffects) - 1,
                                             fw::testing::true_params());
  static Estimator<double> estimator(config);
  static Estimator<float> on_target(default_config<float>(fw::testing::example_motor().cast<float>(), 0,
                                                          [] {
                                                            ParamVector<float> p{};
                                                            const auto d = fw::testing::true_params();
                                                            for (int i = 0; i < kNumParams; ++i) p[i] = float(d[i]);
                                                            return p;
                                                          }()));
  // The cycle's frames, made before counting: two hours of the test duty, a reading every second.
  struct Timed {
    TimeUs t;
    CanFrame f;
  };
  std::vector<Timed> frames;
  frames.reserve(2 * 3600 * 10 * 5);
  fw::testing::Converter converter;
  fw::testing::Plant plant(fw::testing::true_params(), 30.0);
  for (TimeUs t = 0; t < 2 * 3600 * kUsPerS; t += kUsPerS / 10) {
    fw::testing::DriveState s = fw::testing::drive_at(static_cast<double>(t) / kUsPerS);
    s.stator_c = plant.sensor_reading();
    converter.frames_at(t, s, [&](const CanFrame& f) { frames.push_back({t, f}); });
    plant.step(s);
  }
  frames.push_back({frames.back().t + 1, CanFrame{}});  // a sentinel: the last tick's frames are in

  CanFrame out[kMaxOutputFrames];
  long ticks = 0, published = 0;
  double checksum = 0;
  counting = true;  // ---- the real-time section: from here on nothing may allocate ----
  TimeUs tick = 0;
  for (const Timed& f : frames) {
    while (tick < f.t) {
      const EstimatorOutput<double>& o = estimator.tick(tick);
      const EstimatorOutput<float>& of = on_target.tick(tick);
      published += pack_outputs(o, out) + pack_outputs(of, out);
      checksum += o.node_c[0] + of.node_c[0];
      tick += kUsPerS / 10;
      ++ticks;
    }
    estimator.receive(f.f, f.t);
    on_target.receive(f.f, f.t);
  }
  counting = false;  // ---- end of the real-time section ----
  const long realtime_allocations = allocations;

  std::printf("%ld ticks, %zu frames in, %ld frames out, %ld allocations (final stator winding %.2f C)\n", ticks,
              frames.size(), published, realtime_allocations, estimator.output().node_c[0]);
  // The cooling factor's state ran too, in both scalars: estimated (the double one, every effect
  // on against a plant without them, ends frozen in open loop, its sensor judged failed) and moved.
  const bool cooling_ran = estimator.output().cooling_state != CoolingState::off &&
                           on_target.output().cooling_state == CoolingState::tracking &&
                           estimator.output().cooling_factor != 1.0 && on_target.output().cooling_factor != 1.0f;
  if (!cooling_ran)
    std::printf("FAIL: the cooling factor was not estimated (double: state %d, %.4f; float: state %d, %.4f)\n",
                int(estimator.output().cooling_state), estimator.output().cooling_factor,
                int(on_target.output().cooling_state), double(on_target.output().cooling_factor));
  const bool ran = ticks > 70000 && published > kMaxOutputFrames * 70000 && checksum == checksum &&
                   estimator.output().initialized && cooling_ran;
  if (!ran) std::printf("FAIL: the cycle did not run through the estimator\n");
  if (realtime_allocations != 0)
    std::printf("FAIL: the estimator allocated %ld times after start-up\n", realtime_allocations);
  // The counter works: an allocation in the counted state is seen (an explicit call, which the
  // compiler may not elide as it may a new-expression).
  counting = true;
  void* probe = ::operator new(64);
  counting = false;
  const bool counter_works = allocations == realtime_allocations + 1;
  ::operator delete(probe);
  if (!counter_works) std::printf("FAIL: the allocation counter saw nothing\n");
  return ran && realtime_allocations == 0 && counter_works ? 0 : 1;
}
