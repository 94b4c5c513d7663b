// Built with -fno-exceptions -fno-rtti, as the firmware builds the model. Runs an hour at rated
// load in float with every effect on and checks that the result is finite and plausible.
#include <cmath>
#include <cstdio>

#include "lptn/model.hpp"

int main() {
  lptn::MotorConstants<float> m;
  const lptn::EffectSet all = (lptn::EffectSet{1} << lptn::kNumEffects) - 1;
  const lptn::Model<float> model(m, all);
  const auto p = lptn::default_params<float>();
  lptn::Inputs<float> in;
  in.speed_rpm = 1930.f;
  in.torque_nm = 1530.f;
  in.current_a = 103.f;
  in.frequency_hz = 64.9f;
  in.airflow_m3s = 1.f;
  in.ambient_c = 25.f;
  in.has_torque = true;
  float x[lptn::kMaxStates];
  model.initial_state(x, 25.f, 25.f);
  for (int k = 0; k < 36000; ++k) model.step(x, in, p.data(), 0.1f);
  for (int i = 0; i < model.num_states(); ++i) {
    if (!std::isfinite(x[i]) || x[i] < 25.f || x[i] > 400.f) {
      std::printf("state %d = %g out of range\n", i, static_cast<double>(x[i]));
      return 1;
    }
  }
  std::printf("stator winding after 1 h at rated load: %.2f C\n", static_cast<double>(x[0]));
  return 0;
}
