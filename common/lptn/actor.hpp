// The forward pass of a frozen TD3 actor (paper fig. 5: obs -> Linear -> ReLU -> Linear -> ReLU ->
// Linear -> tanh), in float, for the firmware and the host alike. Freestanding: no heap, no
// exceptions, no I/O; the weights are static arrays held elsewhere (an exported header).
//
// Each neuron is b + sum_k w_k x_k, accumulated in float from k = 0 upwards; this reproduces
// libtorch's float output of the same network to about 1e-6 (BLAS sums in another order).
#pragma once

#include <cmath>
#include <cstddef>

namespace lptn {

// A frozen actor: 3 dense layers, row-major weights held elsewhere (static arrays in an exported header).
struct ActorView {
  int inputs, hidden, outputs;
  const float* w1; const float* b1;  // hidden x inputs, hidden
  const float* w2; const float* b2;  // hidden x hidden, hidden
  const float* w3; const float* b3;  // outputs x hidden, outputs
};

namespace actor_detail {
// out[r] = b[r] + sum_c w[r * cols + c] * in[c], optionally through ReLU.
inline void dense(const float* w, const float* b, const float* in, int rows, int cols, bool relu, float* out) {
  for (int r = 0; r < rows; ++r) {
    const float* row = w + static_cast<std::size_t>(r) * static_cast<std::size_t>(cols);
    float acc = 0.0f;
    for (int c = 0; c < cols; ++c) acc += row[c] * in[c];
    acc += b[r];
    out[r] = relu && acc < 0.0f ? 0.0f : acc;  // NaN passes, as in torch.relu
  }
}
}  // namespace actor_detail

// tanh outputs in [-1, 1] written to actions[0..outputs); returns false (and writes nothing) if the
// view's sizes exceed the compile-time bounds (or are not positive). Stack buffers of kMaxHidden
// floats, no heap.
template <int kMaxHidden = 256, int kMaxOutputs = 32>
bool actor_forward(const ActorView& actor, const float* obs, float* actions) {
  static_assert(kMaxHidden > 0 && kMaxOutputs > 0, "bounds must be positive");
  if (actor.inputs <= 0 || actor.hidden <= 0 || actor.outputs <= 0 || actor.hidden > kMaxHidden ||
      actor.outputs > kMaxOutputs)
    return false;
  float h1[kMaxHidden];
  float h2[kMaxHidden];
  float z[kMaxOutputs];
  actor_detail::dense(actor.w1, actor.b1, obs, actor.hidden, actor.inputs, true, h1);
  actor_detail::dense(actor.w2, actor.b2, h1, actor.hidden, actor.hidden, true, h2);
  actor_detail::dense(actor.w3, actor.b3, h2, actor.outputs, actor.hidden, false, z);
  for (int j = 0; j < actor.outputs; ++j) actions[j] = std::tanh(z[j]);
  return true;
}

}  // namespace lptn
