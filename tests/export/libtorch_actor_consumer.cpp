// The whole chain with a real agent: at build time `lptn calibrate --method td3-episode` trains a
// libtorch actor on generated data, `lptn export --actor` writes the header, and this program,
// compiled as the firmware is (-fno-exceptions -fno-rtti, common/ alone), runs the exported
// forward pass and compares it with libtorch's own outputs recorded in the calibration.
#include <cmath>
#include <cstdio>

#include "thermal_calibration.hpp"

namespace cal = lptn::calibration;

int main() {
  int failures = 0;
  double worst = 0;
  bool ran = true;
  for (int i = 0; i < cal::kActorChecks; ++i) {
    float u[32];
    ran = ran && lptn::actor_forward(cal::kActor, cal::kActorCheckObs + 2 * i, u);
    for (int j = 0; j < cal::kActor.outputs; ++j)
      worst = std::fmax(worst, std::fabs(static_cast<double>(u[j]) - cal::kActorCheckActions[cal::kActor.outputs * i + j]));
  }
  std::printf("%s exported forward pass of the %dx%d actor vs libtorch over %d observations: max |diff| %.3g\n",
              ran && worst < 1e-5 ? "ok  " : "FAIL", cal::kActor.hidden, cal::kActor.hidden, cal::kActorChecks, worst);
  failures += !(ran && worst < 1e-5);
  failures += cal::kActorChecks < 4;  // something to compare
  // The constant set the calibration condensed the policy to lies within the bounds it learned in.
  for (int j = 0; j < cal::kActor.outputs; ++j) {
    const double v = cal::kParams[static_cast<std::size_t>(cal::kActorParamIndex[j])];
    const bool inside = v >= cal::kActorParamMin[j] && v <= cal::kActorParamMax[j];
    if (!inside) std::printf("FAIL parameter %d = %g outside [%g, %g]\n", cal::kActorParamIndex[j], v, cal::kActorParamMin[j], cal::kActorParamMax[j]);
    failures += !inside;
  }
  return failures == 0 ? 0 : 1;
}
