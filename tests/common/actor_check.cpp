// Built with -fno-exceptions -fno-rtti, as the firmware builds it: the frozen actor's forward pass
// (lptn/actor.hpp) on a small network worked out by hand, and its refusal of oversized views.
// (tests/td3 checks it against libtorch on a trained 2-256-256-3 actor.)
#include <cmath>
#include <cstdio>

#include "lptn/actor.hpp"

namespace {
int failures = 0;
void check(bool ok, const char* what) {
  if (!ok) {
    std::printf("FAILED: %s\n", what);
    ++failures;
  }
}
}  // namespace

int main() {
  // 2 inputs -> 3 -> 3 -> 2.
  static const float w1[3 * 2] = {1.0f, -2.0f, 0.5f, 0.25f, -1.0f, -1.0f};
  static const float b1[3] = {0.1f, -0.2f, 0.3f};
  static const float w2[3 * 3] = {1.0f, 0.0f, -1.0f, 0.5f, 0.5f, 0.5f, -2.0f, 1.0f, 0.0f};
  static const float b2[3] = {0.0f, 0.1f, 0.2f};
  static const float w3[2 * 3] = {0.3f, -0.6f, 0.9f, 1.0f, 1.0f, -1.0f};
  static const float b3[2] = {-0.1f, 0.05f};
  const lptn::ActorView actor{2, 3, 2, w1, b1, w2, b2, w3, b3};

  const float x[2] = {0.4f, -0.3f};
  // The same in double, written out (layer 1 pre-activations 1.1, -0.075, 0.2).
  double h1[3], h2[3], z[2];
  const double xd[2] = {0.4, -0.3};
  for (int r = 0; r < 3; ++r) {
    const double a = static_cast<double>(w1[2 * r]) * xd[0] + static_cast<double>(w1[2 * r + 1]) * xd[1] + static_cast<double>(b1[r]);
    h1[r] = a > 0 ? a : 0;
  }
  for (int r = 0; r < 3; ++r) {
    double a = static_cast<double>(b2[r]);
    for (int c = 0; c < 3; ++c) a += static_cast<double>(w2[3 * r + c]) * h1[c];
    h2[r] = a > 0 ? a : 0;
  }
  for (int r = 0; r < 2; ++r) {
    double a = static_cast<double>(b3[r]);
    for (int c = 0; c < 3; ++c) a += static_cast<double>(w3[3 * r + c]) * h2[c];
    z[r] = std::tanh(a);
  }
  check(h1[0] > 0 && h1[1] == 0, "the example exercises both sides of the ReLU");

  float out[2] = {0, 0};
  check(lptn::actor_forward(actor, x, out), "actor_forward accepts a 2-3-3-2 network");
  for (int j = 0; j < 2; ++j) check(std::fabs(static_cast<double>(out[j]) - z[j]) < 1e-6, "output matches the hand computation");

  float big[2] = {0, 0};
  const float far[2] = {1e30f, -1e30f};
  check(lptn::actor_forward(actor, far, big) && std::fabs(big[0]) <= 1.0f && std::fabs(big[1]) <= 1.0f,
        "saturated outputs stay in [-1, 1]");

  float untouched[2] = {7.0f, 7.0f};
  check(!lptn::actor_forward<2, 32>(actor, x, untouched), "hidden beyond kMaxHidden is refused");
  check(!lptn::actor_forward<256, 1>(actor, x, untouched), "outputs beyond kMaxOutputs are refused");
  const lptn::ActorView empty{0, 3, 2, w1, b1, w2, b2, w3, b3};
  check(!lptn::actor_forward(empty, x, untouched), "zero inputs are refused");
  check(untouched[0] == 7.0f && untouched[1] == 7.0f, "a refused call writes nothing");

  std::printf("actor: %.6f %.6f (by hand %.6f %.6f)\n", static_cast<double>(out[0]), static_cast<double>(out[1]), z[0], z[1]);
  return failures == 0 ? 0 : 1;
}
