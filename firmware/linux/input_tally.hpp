// How each input reached the model over a replay, and what a replay says of it: `lptn replay` and
// `lptn-daemon --replay` print the same lines (never silently wrong: estimates at rows where an
// input was stale, implausible or replaced are not the motor's as the log has it).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "lptn/firmware/estimator.hpp"
#include "lptn/firmware/estimator_config.hpp"
#include "lptn/firmware/input.hpp"

namespace lptn::fw {

// Ticks (rows) at which one input was stale, implausible (its last value outside its plausible
// range) or substituted (the model ran on its conservative value, or without it for torque and
// voltage), from the status masks each row carries.
struct InputHealth {
  std::size_t stale = 0, implausible = 0, substituted = 0;
};

struct InputTally {
  std::size_t rows = 0;
  std::array<InputHealth, kNumInputs> inputs{};
  void add(const EstimatorOutput<double>& row);
};

// One line per input the model did not get as the log sent it (stale, implausible or substituted
// at any row), naming the log, the share of rows, the input's plausible range and what the model
// ran on instead.
std::vector<std::string> input_warnings(const std::string& log, const InputTally& tally, const EstimatorConfig<double>& config);

}  // namespace lptn::fw
