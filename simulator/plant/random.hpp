#pragma once
// Seeded randomness whose output is the same with every standard library: std::mt19937_64 is
// fully specified, the std distributions are not, so uniform and normal variates are made here.

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

namespace lptn::plant {

// SplitMix64 finaliser: turns (seed, stream) into well-separated engine seeds, so each part of
// the plant (driver, blower, ambient) has its own stream and changing one cannot shift another.
inline std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t stream) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}

  // Uniform on [0, 1) from the top 53 bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  bool chance(double probability) { return uniform() < probability; }

  // Standard normal by Box-Muller (one value per call; determinism matters, speed does not).
  double normal() {
    const double u1 = 1.0 - uniform();  // (0, 1]: log stays finite
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  std::mt19937_64 engine_;
};

// Ornstein-Uhlenbeck noise with standard deviation sigma and correlation time tau, stepped
// exactly (valid for any step): smooth wander instead of white jitter.
class OuNoise {
 public:
  OuNoise(double sigma, double tau_s) : sigma_(sigma), tau_s_(tau_s) {}
  double value() const { return x_; }
  void advance(double dt_s, Rng& rng) {
    const double a = std::exp(-dt_s / tau_s_);
    x_ = a * x_ + sigma_ * std::sqrt(1.0 - a * a) * rng.normal();
  }

 private:
  double sigma_;
  double tau_s_;
  double x_ = 0.0;
};

}  // namespace lptn::plant
