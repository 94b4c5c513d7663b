// diagnose's refits take their steps on the 1 s grid and polish on the data's own (refit.hpp):
// where the data pin the effect they end where a refit on the data's grid alone ends, and where
// the coarse grid keeps no reading (a sensor sampled off the 1 s instants) the fine refit runs
// alone instead of failing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "lptn_testing/small_fleet.hpp"
#include "trainer/calibrate/grid_residuals.hpp"
#include "trainer/diagnose/internal/refit.hpp"
#include "trainer/diagnose/internal/score_test.hpp"
#include "trainer/model/motor_effects.hpp"
#include "trainer/model/simulate.hpp"

namespace lptn::diagnose {
namespace {

constexpr int kCoarse = 10;  // diagnose's factor: 1 s on 10 Hz data

TEST(CoarseRefit, EndsWhereTheFineRefitEndsWhereTheDataPinTheEffect) {
  const auto g = testing::generate({"windage"}, 4, 20, 25, 5);
  const int windage = effect_index("windage");
  model::MotorFile with = g->motor;
  model::enable_effect(with, windage);
  lm::LmSettings lm;
  lm.threads = 2;
  const calibrate::SharedDataset coarse = internal::coarse_dataset(g->dataset, kCoarse);
  const auto fine = internal::refit_with(with, windage, g->calibrated.values, g->dataset, g->split.train, lm, {});
  const auto staged = internal::refit_with(with, windage, g->calibrated.values, g->dataset, g->split.train, lm, {}, &coarse);
  const int w = param_index("windage_base_w");
  std::printf("windage_base_w %.2f W (fine, %d iterations) against %.2f W (coarse, then %d on the fine grid); rmse %.5f "
              "against %.5f K\n", fine.fit.values[w], fine.fit.iterations, staged.fit.values[w], staged.fit.iterations,
              fine.fit.rmse_k, staged.fit.rmse_k);
  ASSERT_TRUE(fine.fit.converged);
  EXPECT_TRUE(staged.fit.converged);
  EXPECT_NEAR(staged.fit.rmse_k, fine.fit.rmse_k, 1e-4);
  // Within a tenth of the fit's own standard error of the same optimum.
  EXPECT_NEAR(staged.fit.values[w], fine.fit.values[w], 0.1 * fine.fit.std_error[w]);
}

TEST(CoarseRefit, WithoutAReadingOnTheCoarseGridTheFineRefitRunsAlone) {
  auto g = testing::generate({}, 3, 10, 12, 6);
  // Every reading the coarse grid would keep (each 1 s instant) masked: none left there.
  for (data::Cycle& c : g->dataset.cycles)
    for (data::Channel ch : {data::Channel::stator_winding_c, data::Channel::rotor_c}) {
      std::vector<float>& v = c.samples[data::index_of(ch)];
      for (std::size_t k = 0; k < v.size(); k += kCoarse) v[k] = std::nanf("");
    }
  const int windage = effect_index("windage");
  model::MotorFile with = g->motor;
  model::enable_effect(with, windage);
  lm::LmSettings lm;
  lm.threads = 2;
  lm.max_iterations = 5;
  const calibrate::SharedDataset coarse = internal::coarse_dataset(g->dataset, kCoarse);
  const auto fine = internal::refit_with(with, windage, g->calibrated.values, g->dataset, g->split.train, lm, {});
  internal::Refit staged;
  ASSERT_NO_THROW(staged = internal::refit_with(with, windage, g->calibrated.values, g->dataset, g->split.train, lm, {},
                                                &coarse));
  EXPECT_EQ(staged.fit.values, fine.fit.values);
  EXPECT_EQ(staged.fit.iterations, fine.fit.iterations);
}

// correct_for_grid: at the baseline the corrected coarse grid's residuals are the data grid's at
// the same instants, where the uncorrected grid's differ by the grid's own error (which a heat
// term would absorb, and which grows with the data).
TEST(CoarseRefit, TheCorrectedGridSeesTheDataGridsMisfitAtTheBaseline) {
  const auto g = testing::generate({}, 3, 20, 25, 8);
  const Model<double> model = g->motor.model();
  const lm::LmReport& at = g->calibrated;
  ASSERT_EQ(at.offsets.size(), g->split.train.size());
  const calibrate::SharedDataset coarse = internal::coarse_dataset(g->dataset, kCoarse);
  calibrate::SharedDataset corrected = coarse;
  internal::correct_for_grid(corrected, g->dataset, model, at.values, g->split.train, at.offsets, 2);
  double worst_corrected = 0, sum_uncorrected = 0;
  std::size_t readings = 0;
  for (std::size_t i = 0; i < g->split.train.size(); ++i) {
    const std::size_t c = g->split.train[i];
    const model::CycleSimulation fine = model::simulate_cycle(model, at.values, g->dataset.cycles[c], at.offsets[i]);
    const model::CycleSimulation on_coarse = model::simulate_cycle(model, at.values, coarse.data.cycles[c], at.offsets[i]);
    for (std::size_t k = 0; k < coarse.data.cycles[c].steps; ++k) {
      const float reading = coarse.data.cycles[c].at(data::Channel::stator_winding_c, k);
      if (std::isnan(reading)) continue;
      const double data_grid = double(fine.stator_sensor[k * kCoarse]) - g->dataset.cycles[c].at(data::Channel::stator_winding_c, k * kCoarse);
      const double uncorrected = double(on_coarse.stator_sensor[k]) - reading;
      const double with_correction = double(on_coarse.stator_sensor[k]) - corrected.data.cycles[c].at(data::Channel::stator_winding_c, k);
      worst_corrected = std::max(worst_corrected, std::abs(with_correction - data_grid));
      sum_uncorrected += (uncorrected - data_grid) * (uncorrected - data_grid);
      ++readings;
    }
  }
  ASSERT_GT(readings, 1000u);
  const double grid_error = std::sqrt(sum_uncorrected / static_cast<double>(readings));
  std::printf("the coarse grid's own error at the baseline: %.4f K RMS; after the correction at most %.2g K\n", grid_error,
              worst_corrected);
  EXPECT_GT(grid_error, 0.005) << "the grid has an error of its own to correct";
  EXPECT_LT(worst_corrected, 1e-4) << "float rounding of the readings, no more";
}

// Half the sum of squared residuals on `dataset`'s training cycles at `values` and each cycle's
// initial offsets (LM's cost), summed here and not by LM.
double cost_on(const model::MotorFile& motor, const ParamVector<double>& values, const data::Dataset& dataset,
               const std::vector<std::size_t>& train, const std::vector<model::InitialOffsets<double>>& offsets) {
  const Model<double> model = motor.model();
  double sum = 0;
  for (std::size_t i = 0; i < train.size(); ++i)
    calibrate::for_each_grid_residual(model, values, dataset.cycles[train[i]], offsets[i], [&](double r) { sum += r * r; });
  return 0.5 * sum;
}

// moved_to_fine and polish_start: a refit on the coarse grid ends at the coarse grid's optimum,
// which on the data's grid is off by the two grids' difference; moved by what the baseline's fits
// on the two grids differ, the coarse baseline itself lands on the data grid's baseline. The polish
// starts from the moved point or the coarse fit's own, whichever costs less on the data's grid, and
// a crawl is evaluated there without a step (kCrawlPolishIterations).
TEST(CoarseRefit, APolishStartsFromTheCoarseFitMovedByTheBaselinesDifferenceOrItsOwnPoint) {
  const auto g = testing::generate({"windage"}, 4, 20, 25, 5);
  const lm::LmReport& fine_baseline = g->calibrated;
  calibrate::SharedDataset coarse = internal::coarse_dataset(g->dataset, kCoarse);
  internal::correct_for_grid(coarse, g->dataset, g->motor.model(), fine_baseline.values, g->split.train,
                             fine_baseline.offsets, 2);
  lm::LmSettings lm;
  lm.threads = 2;
  lm.max_iterations = 15;
  lm::LmSettings from_baseline = lm;
  from_baseline.start_offsets = fine_baseline.offsets;
  const auto coarse_baseline = internal::coarse_stage(g->motor, fine_baseline.values, coarse, g->split.train, from_baseline, {});
  ASSERT_TRUE(coarse_baseline.has_value());
  const int windage = effect_index("windage");
  model::MotorFile with = g->motor;
  model::enable_effect(with, windage);

  // The coarse baseline moved is the data grid's baseline (its windage fixed at the motor file's).
  const lm::LmReport landed = internal::moved_to_fine(with, *coarse_baseline, fine_baseline, *coarse_baseline);
  for (int i = 0; i < kNumParams; ++i)
    EXPECT_NEAR(landed.values[i], fine_baseline.values[i], 1e-12 * std::abs(fine_baseline.values[i])) << param_spec(i).name;
  for (std::size_t k = 0; k < landed.offsets.size(); ++k) {
    EXPECT_NEAR(landed.offsets[k].stator_core, fine_baseline.offsets[k].stator_core, 1e-12);
    EXPECT_NEAR(landed.offsets[k].rotor_core, fine_baseline.offsets[k].rotor_core, 1e-12);
  }

  // From the baseline's offsets the refit finds the windage; from none (diagnose's starts) it ends
  // far above the baseline in its iterations. The polish starts from the cheaper point either way.
  const data::Dataset& fine = g->dataset;
  for (const lm::LmSettings& settings : {from_baseline, lm}) {
    const auto on_coarse = internal::coarse_stage(with, internal::neutral_point(fine_baseline.values, windage), coarse,
                                                  g->split.train, settings, {});
    ASSERT_TRUE(on_coarse.has_value());
    const lm::LmReport moved = internal::moved_to_fine(with, *on_coarse, fine_baseline, *coarse_baseline);
    const double unmoved_cost = cost_on(with, on_coarse->values, fine, g->split.train, on_coarse->offsets);
    const double moved_cost = cost_on(with, moved.values, fine, g->split.train, moved.offsets);
    std::printf("cost on the data's grid: baseline %.3f, the coarse fit's point %.3f, moved %.3f K^2\n",
                fine_baseline.final_cost, unmoved_cost, moved_cost);
    ASSERT_NE(unmoved_cost, moved_cost);
    const lm::LmReport start = internal::polish_start(with, *on_coarse, fine_baseline, *coarse_baseline, g->dataset,
                                                  g->split.train, 2);
    EXPECT_EQ(start.values, moved_cost < unmoved_cost ? moved.values : on_coarse->values);

    lm::LmReport crawled = start;
    crawled.converged = false;
    const internal::Refit polished = internal::polish(with, windage, crawled, g->dataset, g->split.train, lm, {});
    EXPECT_EQ(polished.fit.iterations, 0);
    EXPECT_EQ(polished.fit.values, start.values);
    EXPECT_NEAR(polished.fit.final_cost, std::min(moved_cost, unmoved_cost), 1e-9 * moved_cost)
        << "a crawl is evaluated where it starts";
  }
}

// The likelihood ratios a refit passes through, fed to internal::stop_short_of as LM reports its
// costs: the iteration it is stopped after, or -1 where it runs to the end.
int stopped_after(const std::vector<double>& ratios, double mark, int max_iterations) {
  constexpr double kBaseCost = 1000, kResiduals = 5000;
  const std::function<bool(int, double)> stop = internal::stop_short_of(mark, kBaseCost, kResiduals, max_iterations, 0.1);
  for (std::size_t i = 0; i < ratios.size(); ++i)
    if (stop(static_cast<int>(i), kBaseCost * std::exp(-ratios[i] / kResiduals))) return static_cast<int>(i);
  return -1;
}

TEST(RefitStop, ACrawlShortOfItsMarkStopsAndOneThatCanReachItRunsOn) {
  // Iteration 0 far above the baseline (initial offsets of zero), then a crawl at 0.1 an
  // iteration towards a mark of 6.9: stopped at the first iteration allowed, the fourth.
  std::vector<double> crawl{-500, 1.0};
  for (int i = 2; i <= 15; ++i) crawl.push_back(crawl.back() + 0.1);
  EXPECT_EQ(stopped_after(crawl, 6.9, 15), 4);
  // The same crawl at 0.5 an iteration: twice its pace over the 11 iterations left reaches the
  // mark, so it runs on, until the iterations left at that pace no longer can.
  std::vector<double> faster{-500, 1.0};
  for (int i = 2; i <= 15; ++i) faster.push_back(faster.back() + 0.5);
  const int at = stopped_after(faster, 6.9, 15);
  EXPECT_TRUE(at == -1 || faster[static_cast<std::size_t>(at)] + 2 * 0.5 * (15 - at) < 6.9) << at;
  EXPECT_TRUE(at == -1 || at >= 10) << at;
  // A refit that gains fast is never stopped, whatever its pace does later.
  std::vector<double> effect{-500, 5, 15, 25, 30, 32, 33};
  EXPECT_EQ(stopped_after(effect, 6.9, 15), -1);
  // One pause (a rejected step) among larger gains: the best of the last three sets the pace.
  EXPECT_EQ(stopped_after({-500, 0.5, 1.5, 1.5, 2.5, 2.5}, 6.9, 15), -1);
}

TEST(RefitStop, ARefitThatHasStalledAboveItsMarkStopsAndOneStillGainingRunsOn) {
  // Past its mark of 6.9 at iteration 2, then 0.002 an iteration: once its jump to 7 is out of
  // the last three iterations (at 5), twice its pace over the 10 left is 0.04, below
  // kStalledGain, so it ends there.
  std::vector<double> stalled{-500, 5, 7.0};
  for (int i = 3; i <= 15; ++i) stalled.push_back(stalled.back() + 0.002);
  EXPECT_EQ(stopped_after(stalled, 6.9, 15), 5);
  // At 0.01 an iteration it would gain 0.2 at twice its pace: it runs on, until the iterations
  // left at that pace no longer add kStalledGain (2 x 0.01 x 2 = 0.04 at iteration 13).
  std::vector<double> creeping{-500, 5, 7.0};
  for (int i = 3; i <= 15; ++i) creeping.push_back(creeping.back() + 0.01);
  EXPECT_EQ(stopped_after(creeping, 6.9, 15), 13);
  // Its last iteration is LM's own end: not a stall.
  std::vector<double> steady{-500, 1.0};
  for (int i = 2; i <= 15; ++i) steady.push_back(steady.back() + 0.5);
  EXPECT_NE(stopped_after(steady, 6.9, 15), 15);
}

TEST(RefitStop, AboveTheBaselineOnlyWhereItWouldEndAboveItAnyway) {
  // At -3 and climbing 0.5 an iteration: it would reach the baseline, so it runs on while it
  // can (stopped only once above it, short of the mark, or not at all).
  std::vector<double> climbing{-500, -3.0};
  for (int i = 2; i <= 15; ++i) climbing.push_back(climbing.back() + 0.5);
  const int at = stopped_after(climbing, 6.9, 15);
  EXPECT_TRUE(at == -1 || climbing[static_cast<std::size_t>(at)] >= -0.1) << at;
  // At -3 and climbing 0.01 an iteration: above the baseline either way, stopped.
  std::vector<double> stuck{-500, -3.0};
  for (int i = 2; i <= 15; ++i) stuck.push_back(stuck.back() + 0.01);
  EXPECT_EQ(stopped_after(stuck, 6.9, 15), 4);
  // Just above the baseline (at -0.12, its band 0.1) and creeping 0.002 an iteration: stalled,
  // but twice its pace would take it back into the band, so it is not ended above it.
  std::vector<double> creeping_back{-500, -3.0, -0.12};
  for (int i = 3; i <= 15; ++i) creeping_back.push_back(creeping_back.back() + 0.002);
  const int back = stopped_after(creeping_back, 6.9, 15);
  EXPECT_TRUE(back == -1 || creeping_back[static_cast<std::size_t>(back)] >= -0.1 - 1e-9) << back;
}

}  // namespace
}  // namespace lptn::diagnose
