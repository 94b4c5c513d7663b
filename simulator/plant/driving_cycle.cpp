#include "simulator/plant/driving_cycle.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "simulator/plant/ambient.hpp"
#include "simulator/plant/random.hpp"
#include "simulator/plant/route_profile.hpp"
#include "simulator/plant/train_run.hpp"

namespace lptn::plant {
namespace {

constexpr double kMaxInternalStep_s = 0.25;  // braking to a mark needs finer steps than the output

enum Stream : std::uint64_t { kDriverStream = 10, kBlowerStream = 20, kAmbientStream = 30 };

}  // namespace

std::vector<DriveSample> drive_cycle(CycleKind kind, const MotorSpec& motor, const TrainSpec& train,
                                     const BlowerPolicy& blower_policy, double duration_s, double dt_s,
                                     std::uint64_t seed) {
  if (!(dt_s > 0.0)) throw std::invalid_argument("drive_cycle: dt_s must be > 0");
  if (!(duration_s >= 0.0)) throw std::invalid_argument("drive_cycle: duration_s must be >= 0");

  const auto substeps = static_cast<int>(std::ceil(dt_s / kMaxInternalStep_s - 1e-9));
  const double h = dt_s / substeps;
  const auto count = static_cast<std::size_t>(std::floor(duration_s / dt_s + 1e-9)) + 1;

  TrainRun run(kind, motor, train, derive_seed(seed, kDriverStream));
  Blower blower(blower_policy, motor.rated_power_w, derive_seed(seed, kBlowerStream));
  Ambient ambient(route_profile(kind).tunnels, derive_seed(seed, kAmbientStream));

  std::vector<DriveSample> out;
  out.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    DriveSample sample{};
    for (int k = 0; k < substeps; ++k) {
      const TrainRun::Command cmd = run.step(h);
      if (k == 0) {
        sample = {static_cast<double>(i) * dt_s, cmd.speed_rpm, cmd.torque_nm, blower.airflow_m3s(),
                  ambient.value_c()};
      }
      const double power_w = cmd.torque_nm * cmd.speed_rpm * 2.0 * std::numbers::pi / 60.0;
      blower.advance(h, power_w);
      ambient.advance(h, cmd.moving);
    }
    out.push_back(sample);
  }
  return out;
}

}  // namespace lptn::plant
