// The drift's per-cycle factor is the minimum of that cycle's error over the group's factor: on
// cycles near factor 1 (found by a parabola through the baseline and a step to either side) and
// on cycles whose cooling weakened by a fifth or more (outside that step: Brent's minimizer on the
// whole range). Checked against the error itself, not against either minimizer.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "lptn_testing/small_fleet.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/diagnose/drift.hpp"

namespace lptn::diagnose {
namespace {

// Both sensors' squared error of `cycle` at `p` (the drift's own measure of a factor).
double squared_error(const Model<double>& model, const ParamVector<double>& p, const data::Cycle& cycle) {
  const calibrate::CycleMetrics m = calibrate::evaluate_cycle(model, p, cycle);
  double sse = 0;
  for (const model::ErrorMetrics* e : {&m.stator, &m.rotor})
    if (e->samples) sse += e->rmse_k * e->rmse_k * static_cast<double>(e->samples);
  return sse;
}

// Each cycle's factor against the error on either side, `h` away in log c: a factor within h/2
// of the minimum of a parabola has no lower error there. Counts the factors within the parabola's
// step of 1 and beyond it.
void expect_minima(const testing::Generated& g, const diagnose::Drift& d, double h, int& near_one, int& far) {
  const Model<double> model = g.motor.model();
  ASSERT_EQ(d.factors.size(), g.dataset.cycles.size());
  for (std::size_t i = 0; i < d.factors.size(); ++i) {
    const data::Cycle& cycle = g.dataset.cycles[i];
    const double c = d.factors[i].factor;
    const auto error = [&](double factor) {
      return squared_error(model, diagnose::scaled_group(g.calibrated.values, d.group, factor), cycle);
    };
    const double at = error(c), below = error(c * std::exp(-h)), above = error(c * std::exp(h));
    std::printf("%s: factor %.5f, error %.6g (%+.3g below, %+.3g above)\n", cycle.name.c_str(), c, at, below - at,
                above - at);
    EXPECT_LE(at, below) << cycle.name;
    EXPECT_LE(at, above) << cycle.name;
    (std::abs(std::log(c)) < 0.02 ? near_one : far) += 1;
  }
}

TEST(Drift, EachCyclesFactorIsTheMinimumOfItsErrorNearOneAndFarFromIt) {
  // To within kLogFactorTolerance (1e-4 in log c, a fiftieth of the factor's resolution): no
  // lower error 2e-4 to either side.
  constexpr double h = 2e-4;
  int near_one = 0, far = 0;
  // A clean dump: every factor near 1. Cooling that fouls from the fifth cycle on
  // (simulator/generate/plant_physics.hpp): factors a fifth weaker and more, beyond the step.
  const auto clean = testing::generate({}, 6, 20, 25, 5);
  const diagnose::Drift d = diagnose::find_drift(clean->motor.model(), clean->calibrated.values, clean->dataset, 2);
  expect_minima(*clean, d, h, near_one, far);
  const auto fouling = testing::generate({}, 9, 20, 25, 5, {}, gen::plant_bit(gen::PlantPhysics::cooling_fouling));
  const diagnose::Drift f = diagnose::find_drift(fouling->motor.model(), fouling->calibrated.values, fouling->dataset, 2);
  ASSERT_EQ(f.group, diagnose::DriftGroup::cooling);
  expect_minima(*fouling, f, h, near_one, far);
  // Both ways of finding it were asked.
  EXPECT_GE(near_one, 4);
  EXPECT_GE(far, 3);
}

}  // namespace
}  // namespace lptn::diagnose
