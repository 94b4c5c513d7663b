// Where a sensor's residual lies: the operating region it is largest in, and the inputs it follows.
// What the verdict on the model (adequacy.hpp) says besides "something is missing", so that a user
// reads "worst at high speed; follows speed" before opening the report.
//
// Constant memory whatever the data: the regions are the speed and current tertiles of the dump
// (from a 256-bin histogram), and the residual is reduced to sums as each cycle is simulated.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "trainer/data/dataset.hpp"
#include "trainer/diagnose/adequacy.hpp"

namespace lptn::diagnose::internal {

// The inputs a residual may follow, each through a first-order lag of kFollowTauS: a thermal
// residual answers an input's recent history, not its present value.
inline constexpr std::size_t kFollowInputs = 6;
inline constexpr double kFollowTauS = 600;
// A correlation below this is not reported as "follows".
inline constexpr double kFollowMin = 0.3;
// A region with less than this share of the readings is not named the worst.
inline constexpr double kRegionMinShare = 0.05;
// The window over which a sensor's own rate of warming is taken (its readings' noise averages out;
// a thermal node's response is minutes).
inline constexpr double kWarmingWindowS = 300;
// The lags (s) at which the residual's autocorrelation is measured for its correlation time: from
// the readings' own period to beyond the slowest node.
inline constexpr std::array<double, 18> kShapeLagsS = {1,   2,   5,   10,   20,   30,   60,   120,  180,
                                                       300, 420, 600, 900, 1200, 1800, 2700, 3600, 5400};

// Speed and current tertile edges over the cycles (at 1 Hz), for the regions.
struct RegionEdges {
  std::array<double, 2> speed{}, current{};  // lower and upper tertile edges
  std::array<double, 2> speed_range{}, current_range{};  // min and max seen
};
RegionEdges region_edges(const data::Dataset& dataset, const std::vector<std::size_t>& cycles);

// Sums of one sensor's residual against the inputs and in the regions; added over cycles.
struct WhereSums {
  double n = 0, sr = 0, srr = 0;
  std::array<double, kFollowInputs> n_in{}, sx{}, sxx{}, sxr{}, sr_in{}, srr_in{};
  std::array<double, 9> region_n{}, region_rr{};  // speed tertile * 3 + current tertile
  // The shape: per lag, pairs of residuals that far apart (sums of a, b, a*b) for the
  // autocorrelation; the residual against the sensor's rate of warming (w) and rise over ambient (u).
  std::array<double, kShapeLagsS.size()> lag_n{}, lag_sa{}, lag_sb{}, lag_sab{};
  double nw = 0, sw = 0, sww = 0, swr = 0, srw = 0, srrw = 0;
  double nu = 0, su = 0, suu = 0, sur = 0, sru = 0, srru = 0;
  WhereSums& operator+=(const WhereSums& o);
};
// `residual` per grid step (NaN where the sensor has no reading) of the sensor read on `sensor`;
// taken at 1 Hz.
WhereSums where_sums(const data::Cycle& cycle, data::Channel sensor, const std::vector<float>& residual,
                     const RegionEdges& edges);

Where where(const WhereSums& sums, const RegionEdges& edges);
Shape shape(const WhereSums& sums);

}  // namespace lptn::diagnose::internal
