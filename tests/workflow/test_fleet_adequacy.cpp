// A fleet's calibration judged adequate or not (trainer/workflow/calibration_adequacy): each
// motor's cycles with its own cooling factor against the fleet's sensors' noise. Label fleet: hours
// of simulated data, left out of the sanitizer run (the fleet path runs there in
// Workflow.AFleetIsCalibratedWithEachMotorsCooling, which judges its adequacy too).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "lptn_testing/temp_dir.hpp"
#include "simulator/generate/generate.hpp"
#include "simulator/generate/plant_physics.hpp"
#include "trainer/workflow/calibrate.hpp"

#include "generated_fleet.hpp"

namespace lptn::workflow {
namespace {

// A fleet that is the model exactly, whose weak motor's one cycle falls in the test split: the
// type's pooled metrics (as if one motor had driven every cycle) are then 4x worse on test than on
// train, which says where the weak motor's cycles went, not that the fit learnt its training
// cycles. Its status is ok: each motor with its own factor is at its sensors' noise.
TEST(WorkflowAdequacy, AFleetWhoseWeakMotorIsInTheTestSplitIsNotCalledOverfitted) {
  testing::TempDir t;
  gen::FleetOptions o;
  o.motors = 5;
  o.motor.cycles = 1;
  o.motor.seed = 7;
  o.motor.min_duration_s = 30 * 60;
  o.motor.max_duration_s = 40 * 60;
  const calibrate::CalibrationRequest q = generate_fleet_request(o, t.path()).request;
  const FleetCalibration f = calibrate_fleet(q, {});
  ASSERT_GT(f.result.test.stator.rmse_k, 2 * f.result.train.stator.rmse_k) << "the weak motor should be in the test split";
  std::string all;
  for (const calibrate::CalibrationWarning& w : f.result.warnings) all += w.code + ": " + w.message + "\n";
  EXPECT_EQ(f.result.status, calibrate::kStatusOk) << all;
}

// A fleet whose motors all have friction growing with speed cubed, which the paper's model lacks:
// each motor is two to five times its sensors' noise off with its own cooling factor, and the
// fleet's calibration says so, once per sensor, naming the motors.
TEST(WorkflowAdequacy, AFleetThatLacksThePlantsPhysicsIsWarnedOncePerSensor) {
  testing::TempDir t;
  gen::FleetOptions o;
  o.motors = 3;
  o.motor.cycles = 2;
  o.motor.seed = 3;
  o.motor.min_duration_s = 20 * 60;
  o.motor.max_duration_s = 25 * 60;
  o.motor.plant = gen::plant_bit(gen::PlantPhysics::windage_cubed);
  const calibrate::CalibrationRequest q = generate_fleet_request(o, t.path()).request;
  const FleetCalibration f = calibrate_fleet(q, {});
  EXPECT_EQ(f.result.status, calibrate::kStatusWarnings);
  std::vector<std::string> inadequate;
  for (const calibrate::CalibrationWarning& w : f.result.warnings)
    if (w.code == "not_adequate") inadequate.push_back(w.message);
  ASSERT_GE(inadequate.size(), 1u);
  ASSERT_LE(inadequate.size(), 2u) << "one per sensor, not one per motor";
  const std::string& rotor = inadequate.back();
  EXPECT_EQ(rotor.rfind("the model is not adequate on the rotor sensor on ", 0), 0u) << rotor;
  EXPECT_NE(rotor.find("each with its own cooling factor"), std::string::npos) << rotor;
  EXPECT_NE(rotor.find("(worst: motor_0"), std::string::npos) << rotor;
  double worst_rotor = 0;
  for (const fleet::FleetMotorResult& m : f.fit.motors) worst_rotor = std::max(worst_rotor, m.metrics.rotor.rmse_k);
  EXPECT_GT(worst_rotor, 2.0 * 0.5);  // the rotor sensor's noise
}

}  // namespace
}  // namespace lptn::workflow
