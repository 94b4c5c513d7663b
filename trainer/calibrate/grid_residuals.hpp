// The residuals every least-squares fit of a cycle uses (fit_lm, the fleet's cooling factors):
// model minus measurement of the stator winding sensor and, where measured, the rotor, on the grid.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "trainer/model/simulate.hpp"

namespace lptn::calibrate {

// How many residuals the first `max_steps` grid steps of `cycle` give (its samples must be here: a
// shared dataset's remote cycle has its count in its CycleShare, DatasetRef::residuals).
inline std::size_t count_grid_residuals(const data::Cycle& cycle, std::size_t max_steps = SIZE_MAX) {
  std::size_t n = 0;
  const std::size_t steps = max_steps < cycle.steps ? max_steps : cycle.steps;
  for (std::size_t k = 1; k < steps; ++k)
    n += static_cast<std::size_t>(!std::isnan(cycle.at(data::Channel::stator_winding_c, k))) +
         static_cast<std::size_t>(!std::isnan(cycle.at(data::Channel::rotor_c, k)));
  return n;
}

// Runs the cycle and hands each residual (model - measured) to `put` in a fixed order: per grid
// step after the first, the stator then the rotor, where measured. (Grid step 0 is the initial
// state, which starts at the measurement by construction.) False if the numbers left finite.
template <class T, class Put>
bool for_each_grid_residual(const Model<double>& model, const ParamVector<T>& p, const data::Cycle& cycle,
                            const model::InitialOffsets<T>& start, Put&& put, std::size_t max_steps = SIZE_MAX,
                            const model::PreparedCycle* prepared = nullptr) {
  bool finite = true;
  model::run_cycle(model, p.data(), cycle, [&](std::ptrdiff_t k, const T* x) {
    if (k < 0) return;
    const auto grid = static_cast<std::size_t>(k + 1);
    const float ys = cycle.at(data::Channel::stator_winding_c, grid);
    const float yr = cycle.at(data::Channel::rotor_c, grid);
    if (!std::isnan(ys)) put(model.stator_sensor(x) - T(ys));
    if (!std::isnan(yr)) put(model.rotor_sensor(x) - T(yr));
    finite = finite && std::isfinite(value_of(x[0]));
  }, start, max_steps, prepared);
  return finite;
}

}  // namespace lptn::calibrate
