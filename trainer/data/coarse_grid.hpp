// A cycle on a coarser grid, for calibrators that score many parameter sets (TD3's sequential
// formulation): `factor` times fewer model steps, the same thermal story.
#pragma once

#include "trainer/data/dataset.hpp"

namespace lptn::data {

// The cycle on the grid t0 + k * factor * dt. The simulation advances from grid step k to k + 1
// with the inputs held at step k, so each coarse step's inputs stand for the fine steps they
// replace: their mean, except the current, whose root mean square keeps the copper losses (I^2)
// the fine steps would have produced. Measurements (the sensors) are sampled, not averaged: a
// coarse step compares the model with the reading at its own instant. A channel with no valid
// sample among the fine steps is NaN there. factor 1 returns the cycle unchanged; factor < 1
// throws std::invalid_argument.
Cycle coarse_grid(const Cycle& cycle, int factor);

}  // namespace lptn::data
