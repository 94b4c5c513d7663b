// What a parameter set earns on cycles: model-minus-measurement statistics per cycle and pooled,
// the figures calibration.json reports for its train and test split.
#pragma once

#include <string>
#include <vector>

#include "trainer/model/simulate.hpp"

namespace lptn::calibrate {

// Model-minus-measurement statistics of one cycle; rotor.samples == 0 where the rotor is not measured.
struct CycleMetrics {
  std::string name;
  ErrorMetrics stator;
  ErrorMetrics rotor;
};

// One side of the split: every cycle and the pooled figures.
struct SplitMetrics {
  ErrorMetrics stator;
  ErrorMetrics rotor;
  std::vector<CycleMetrics> cycles;
};

}  // namespace lptn::calibrate
