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
  WhereSums& operator+=(const WhereSums& o);
};
// `residual` per grid step (NaN where the sensor has no reading); taken at 1 Hz.
WhereSums where_sums(const data::Cycle& cycle, const std::vector<float>& residual, const RegionEdges& edges);

Where where(const WhereSums& sums, const RegionEdges& edges);

}  // namespace lptn::diagnose::internal
