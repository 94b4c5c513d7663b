// The exported header as the firmware uses it: compiled with -fno-exceptions -fno-rtti against
// common/ alone (no trainer library), from a header that `lptn export` wrote at build time. Builds
// the calibrated model, heats it for an hour at a constant load and checks that it heads for a
// plausible steady state; checks the actor's forward pass against the trainer's check values.
// A plain program (GoogleTest needs exceptions); ctest reads its exit code.
#include <cmath>
#include <cstdio>

#include "lptn/internal/small_lu.hpp"
#include "thermal_calibration.hpp"

namespace cal = lptn::calibration;

namespace {

int failures = 0;

void check(bool ok, const char* what, double value) {
  std::printf("%s %s (%.6g)\n", ok ? "ok  " : "FAIL", what, value);
  if (!ok) ++failures;
}

// The motor's constants are a compile-time value: the firmware may put them in flash.
constexpr lptn::MotorConstants<double> kMotor = cal::motor_constants();
static_assert(kMotor.pole_pairs == 2 && kMotor.harmonic_points == 5, "the fixture's motor");
static_assert(cal::kEffects == lptn::effect_bit(lptn::effect_index("airgap")), "the fixture enables the air gap only");

// About rated load, blower at full airflow.
lptn::Inputs<double> rated_load() {
  lptn::Inputs<double> in;
  in.speed_rpm = 1930;
  in.torque_nm = 1530;
  in.current_a = 103;
  in.frequency_hz = 64.9;
  in.airflow_m3s = 1;
  in.ambient_c = 25;
  in.has_torque = true;
  return in;
}

void check_model() {
  const lptn::Model<double> model(cal::motor_constants(), cal::kEffects);
  const lptn::Inputs<double> in = rated_load();
  const double* p = cal::kParams.data();

  // The steady state of the step's linear system: A x + c = 0.
  lptn::HeatBalance<double> sys;
  model.assemble(in, p, sys);
  lptn::internal::SmallLu<double> lu;
  double steady[lptn::kMaxStates];
  for (int i = 0; i < sys.n; ++i) steady[i] = -sys.c[i];
  if (!lu.factor(sys.a, sys.n)) {
    check(false, "the network's matrix is regular", 0);
    return;
  }
  lu.solve(steady);
  check(steady[lptn::kStatorWinding] > 60 && steady[lptn::kStatorWinding] < 200,
        "steady stator winding temperature at rated load is plausible (60..200 C)", steady[lptn::kStatorWinding]);
  check(steady[lptn::kRotorWinding] > 60 && steady[lptn::kRotorWinding] < 250,
        "steady rotor winding temperature at rated load is plausible (60..250 C)", steady[lptn::kRotorWinding]);

  double x[lptn::kMaxStates];
  model.initial_state(x, in.ambient_c, in.ambient_c);
  for (int k = 0; k < 36000; ++k) model.step(x, in, p, 0.1);  // one hour at 0.1 s
  bool between = true;
  for (int i = 0; i < model.num_states(); ++i)
    between = between && std::isfinite(x[i]) && x[i] > in.ambient_c && x[i] <= steady[i] + 1e-6;
  check(between, "after 1 h every node lies between ambient and its steady state", x[lptn::kStatorWinding]);
  const double rise = (x[lptn::kStatorWinding] - in.ambient_c) / (steady[lptn::kStatorWinding] - in.ambient_c);
  check(rise > 0.6, "after 1 h the stator winding has risen more than 60 % of the way", rise);

  for (int k = 0; k < 10 * 36000; ++k) model.step(x, in, p, 0.1);  // ten hours more
  double worst = 0;
  for (int i = 0; i < model.num_states(); ++i) worst = std::fmax(worst, std::fabs(x[i] - steady[i]));
  check(worst < 0.01, "after 11 h the model sits at the steady state (K)", worst);
}

void check_actor() {
  static_assert(cal::kActor.inputs == 2 && cal::kActor.outputs == 3);
  double worst = 0;
  bool ran = true;
  for (int i = 0; i < cal::kActorChecks; ++i) {
    float u[3];
    ran = ran && lptn::actor_forward(cal::kActor, cal::kActorCheckObs + 2 * i, u);
    for (int j = 0; j < cal::kActor.outputs; ++j)
      worst = std::fmax(worst, std::fabs(static_cast<double>(u[j]) - cal::kActorCheckActions[cal::kActor.outputs * i + j]));
  }
  check(ran, "actor_forward accepts the exported actor", cal::kActorChecks);
  check(worst < 1e-5, "actor_forward matches the check actions (max abs difference)", worst);
  // The observation map and the parameter map as the firmware would apply them.
  const float obs[2] = {static_cast<float>((1930 - cal::kActorObsOffset[0]) / cal::kActorObsScale[0]),
                        static_cast<float>((1530 - cal::kActorObsOffset[1]) / cal::kActorObsScale[1])};
  float u[3];
  lptn::actor_forward(cal::kActor, obs, u);
  bool within = true;
  for (int j = 0; j < 3; ++j) {
    const double v = lptn::from_normalized(static_cast<double>(u[j]), cal::kActorParamMin[j], cal::kActorParamMax[j]);
    within = within && v >= cal::kActorParamMin[j] && v <= cal::kActorParamMax[j];
  }
  check(within, "the actor's parameters stay within their bounds", u[0]);
}

}  // namespace

int main() {
  std::printf("calibration: %s of %s, %s (test RMSE stator %.3f K)\n", cal::kMethod, cal::kMotorName, cal::kCreatedUtc,
              cal::kTestRmseStatorK);
  check_model();
  check_actor();
  return failures == 0 ? 0 : 1;
}
