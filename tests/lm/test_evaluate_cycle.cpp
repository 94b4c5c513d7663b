// evaluate_cycle compares as the model runs, without storing the simulation; its metrics must be
// simulate_and_evaluate's to the bit (the drift's factors and every calibration's split metrics
// come from evaluate_cycle).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "lptn_testing/error_metrics.hpp"
#include "lptn_testing/fleet_dump.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/model/simulate.hpp"

namespace lptn::lm {
namespace {

TEST(EvaluateCycle, MetricsAreSimulateAndEvaluatesToTheBit) {
  testing::Dump d;
  testing::generate_dump(d, 2, 5, 600, 900, 0.5);
  std::vector<data::Cycle> cycles = d.dataset.cycles;
  // Readings missing in stretches, and a cycle without its rotor telemetry.
  data::Cycle gaps = cycles[0];
  gaps.name += "-gaps";
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (data::Channel ch : {data::Channel::stator_winding_c, data::Channel::rotor_c}) {
    std::vector<float>& v = gaps.samples[data::index_of(ch)];
    for (std::size_t k = 0; k < v.size(); ++k)
      if ((k / 700) % 3 == 1) v[k] = nan;
  }
  cycles.push_back(gaps);
  data::Cycle no_rotor = cycles[1];
  no_rotor.name += "-no-rotor";
  for (float& v : no_rotor.samples[data::index_of(data::Channel::rotor_c)]) v = nan;
  cycles.push_back(no_rotor);

  const Model<double> model = d.motor.model();
  const ParamVector<double> guess = d.motor.initial_values();
  const ParamVector<double> off = [&] {  // further off the plant: errors of kelvins
    ParamVector<double> p = guess;
    for (int i : {kLambda1s, kLambda2r}) p[i] *= 1.3;
    return p;
  }();
  std::size_t rotor_cycles = 0;
  for (const data::Cycle& cycle : cycles)
    for (const ParamVector<double>* p : {&guess, &off}) {
      const model::PreparedCycle prepared = model::prepare_cycle(model, cycle);
      const calibrate::CycleMetrics stored = calibrate::simulate_and_evaluate(model, *p, cycle).metrics;
      ASSERT_GT(stored.stator.samples, 0u) << cycle.name;
      rotor_cycles += stored.rotor.samples > 0;
      for (const model::PreparedCycle* with : {static_cast<const model::PreparedCycle*>(nullptr), &prepared}) {
        const calibrate::CycleMetrics streamed = calibrate::evaluate_cycle(model, *p, cycle, with);
        EXPECT_EQ(streamed.name, cycle.name);
        testing::expect_same_metrics(streamed.stator, stored.stator, cycle.name + ", stator");
        testing::expect_same_metrics(streamed.rotor, stored.rotor, cycle.name + ", rotor");
      }
    }
  EXPECT_EQ(rotor_cycles, 2u * 3u);  // every cycle but the one without the rotor, at both sets
}

}  // namespace
}  // namespace lptn::lm
