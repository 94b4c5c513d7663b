// A candump log through the estimator into a CSV of estimates (written atomically), with a
// progress line and malformed lines reported: what `lptn replay` and `lptn vcan-bench` run.
#pragma once

#include <string>

#include "lptn/firmware/estimator_config.hpp"
#include "replay.hpp"

namespace lptn {

// Throws std::invalid_argument (bad input: a log that cannot be read or holds no frame) or
// std::runtime_error (the output could not be written); nothing is left at `csv` then.
fw::ReplayStats replay_to_csv(const std::string& log, const fw::EstimatorConfig<double>& config, const std::string& csv,
                              bool quiet);

}  // namespace lptn
