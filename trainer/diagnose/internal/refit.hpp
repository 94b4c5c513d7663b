// The refit with one effect added, and whether the data can tell the effect apart.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "trainer/lm/lm.hpp"

namespace lptn::diagnose::internal {

// Why the refit cannot pin the effect, as sentence fragments naming the parameter (empty: it can).
struct Refit {
  lm::LmReport fit;
  std::string confounded;  // correlated beyond the flag with a parameter the model has: a property of the data
  std::string imprecise;   // a standard error beyond the value (or none at all)
};

// `fine`'s cycles on a grid `factor` times coarser (data::coarse_grid: the 1 s grid TD3 scores on
// at 10), shared over the processes as `fine` is (each remote cycle's residual count its own).
calibrate::SharedDataset coarse_dataset(calibrate::DatasetRef fine, int factor);

// `coarse` (coarse_dataset of `fine`) with its own error taken out at `at`: each training cycle's
// readings shifted by what the coarse grid's simulation differs from the data's at the same
// instants (multigrid's tau correction), both from the cycles' `offsets` (the baseline fit's, in
// `train`'s order). At `at` the coarse residuals are then the data grid's at those instants, and
// near it a coarse fit sees the data's misfit, not the grid's: unlike the grid's own error (copper
// losses of currents that change within a second, a step of 1 s instead of 0.1 s), which a heat
// term absorbs and which grows with the data (on a clean 48 h dump, dictionary scores of 10 where
// the data grid's are 3), a score or a likelihood ratio on the corrected grid is the data's.
void correct_for_grid(calibrate::SharedDataset& coarse, calibrate::DatasetRef fine, const Model<double>& model,
                      const ParamVector<double>& at, const std::vector<std::size_t>& train,
                      const std::vector<model::InitialOffsets<double>>& offsets, int threads);

// fit_lm of `with_effect` (the calibrated motor with `effect` switched on) from `start`: the
// baseline's values with the effect's at one of diagnose's starts (the score test's Gauss-Newton
// step, or the neutral value: from the step alone, or from the motor file's initial guess, a refit
// of a few iterations can end worse than the baseline; diagnose.cpp keeps the better of the two).
// With `coarse` (coarse_dataset of `dataset`): coarse_stage, then polish (below). Without a
// reading on the coarse grid, the fine fit alone.
Refit refit_with(const model::MotorFile& with_effect, int effect, const ParamVector<double>& start, calibrate::DatasetRef dataset,
                 const std::vector<std::size_t>& train, const lm::LmSettings& settings, const lm::LmProgress& progress,
                 const calibrate::SharedDataset* coarse = nullptr);

// The fit on `coarse` alone, a tenth of the work per iteration: where a start leads. Empty where
// the coarse grid keeps no reading of the training cycles (a sensor sampled off its 1 s instants:
// the fit must run on the data's own grid). diagnose compares its starts here and polishes the
// better one only: the polish costs ten times a coarse iteration.
std::optional<lm::LmReport> coarse_stage(const model::MotorFile& with_effect, const ParamVector<double>& start,
                                     calibrate::DatasetRef coarse, const std::vector<std::size_t>& train,
                                     const lm::LmSettings& settings, const lm::LmProgress& progress);

// `on_coarse` (a refit of `with_effect` on the coarse grid) moved onto the data's grid by what the
// baseline's fit there (`fine_baseline`) differs from its refit on the coarse grid
// (`coarse_baseline`): each free parameter in its internal coordinate (held within its bounds),
// each training cycle's initial offsets (multigrid's correction of the solution). The two grids'
// optima differ by more than a refit moves from its baseline, so the coarse fit's own point is no
// start on the data's grid: on the clean 200 h dump it was 0.393 K there against the baseline's
// 0.3755, and the polish spent its iterations coming back down (windage's likelihood ratio 2.7
// after three of them; from the moved point 4.7 at the start and after three alike).
lm::LmReport moved_to_fine(const model::MotorFile& with_effect, const lm::LmReport& on_coarse, const lm::LmReport& fine_baseline,
                       const lm::LmReport& coarse_baseline);

// Where diagnose polishes `on_coarse`: moved_to_fine of it, or the coarse fit's own point where
// that costs less on `dataset`'s grid (two simulations of the training cycles, against one
// differentiated one per polish iteration). The move is a first-order correction: on the 200 h
// dump's crawls it is what makes the polish start at the baseline's footing (the cycles' initial
// offsets most of all: the parameters moved alone started a likelihood ratio of -5500 below it),
// but on short cycles with a windage that the data pin, the coarse fit's own offsets were closer.
lm::LmReport polish_start(const model::MotorFile& with_effect, const lm::LmReport& on_coarse, const lm::LmReport& fine_baseline,
                      const lm::LmReport& coarse_baseline, calibrate::DatasetRef dataset, const std::vector<std::size_t>& train,
                      int threads);

// The fit on `dataset` from where `on_coarse` ended (its parameters and the cycles' initial
// offsets): the result is the fit on `dataset`, and its iterations are the polish's. Where the data
// pin the effect the polish takes a few iterations to the same optimum; along a flat direction (an
// absent effect) it ends elsewhere on it than a fit without the coarse stage would (docs/hardening.md, "Scale:
// a fleet dump of 200 hours"). After a coarse fit that used up its iterations, at most
// kCrawlPolishIterations: none, which from moved_to_fine's start is the fit there (on the clean
// 200 h dump three iterations from it moved the crawls' likelihood ratios by 0.0 to 0.16, at 2.6 s
// each). diagnose polishes moved_to_fine of the coarse fit; refit_with the coarse fit itself.
Refit polish(const model::MotorFile& with_effect, int effect, const lm::LmReport& on_coarse, calibrate::DatasetRef dataset,
             const std::vector<std::size_t>& train, const lm::LmSettings& settings, const lm::LmProgress& progress);

constexpr int kCrawlPolishIterations = 0;

// A refit that cannot reach `mark` (a likelihood ratio against a fit of cost `base_cost`, counting
// `effective_residuals`) in the iterations it has left at kPaceMargin times the best pace of its
// last kPaceIterations: LmSettings::stop for a refit of at most `max_iterations`, which ends it.
// An absent effect's refit crawls along its flat direction for all its iterations (a term's size
// towards nothing with its exponent free: 15 coarse iterations from each start, 3.4 s of the clean
// 48 h dump's diagnosis, for a likelihood ratio of 3.1 where 6.9 would buy a polish), and where it
// stops it is still short of the mark that decides its verdict; the ratio shown is then where the
// crawl stopped, below where it would have ended. A crawl's pace varies from one iteration to the
// next (LM's trust region grows and shrinks), hence the margin: at the pace alone a crawl on the
// clean 200 h dump was stopped at 0.9 where its 15 iterations reached the polish's 6.9. A refit
// above the baseline (a ratio below -at_baseline) is ended only where it would end there too
// (listed as failed either way), and none before kPaceIterations: LM's first steps gain the most
// (the first, from initial offsets of zero, most of all).
// A polish from moved_to_fine's start is judged after its first iteration: it starts where the
// coarse fit's gain already is, not at LM's large first steps (on the clean 200 h dump its three
// iterations moved the likelihood ratios by 0.0, 0.08 and 0.16, each at 2.6 s).
inline constexpr int kPaceIterations = 3;
inline constexpr int kPolishPaceIterations = 1;
inline constexpr double kPaceMargin = 2.0;
// A refit that at kPaceMargin times its pace would gain less than this likelihood ratio in the
// iterations it has left has stalled, and is ended too, above its mark as below it (and above the
// baseline only where it would end there too, as above): above its mark the refit is polished (or
// kept) either way, so what the rest of its crawl would add is its ratio's last digits, not its
// verdict. Its last iteration is LM's own end, not a stall. "Would" at its recent
// pace: LM lengthens its steps again after small ones, so a stalled crawl can still gain more than
// this. On the clean 200 h dump (FLEET_MOTORS=0 scripts/bench-scale.sh 200) windage's refit from
// its neutral value stalled at 6.41 after 5 of its 15 coarse iterations and the 10 more gained
// 0.17; with it ended there its polished ratio is 4.51 instead of 4.68, the two dictionary terms'
// 7.03 are 7.026 and 6.998, every verdict is the same, and the diagnosis took 69 s instead of 82.
inline constexpr double kStalledGain = 0.05;
std::function<bool(int iteration, double cost)> stop_short_of(double mark, double base_cost, double effective_residuals,
                                                              int max_iterations, double at_baseline,
                                                              int pace_iterations = kPaceIterations);

// `fit` (of `with_effect`, on any grid) with what the data can tell of the effect in it.
Refit judged(lm::LmReport fit, const model::MotorFile& with_effect, int effect);

}  // namespace lptn::diagnose::internal
