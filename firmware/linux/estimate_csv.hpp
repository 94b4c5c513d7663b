// The estimator's output, one CSV row per tick. The first columns are the fleet-dump contract's
// (time_s and the inputs exactly as the model ran on them, the sensor readings it saw), so that a
// replay's CSV loads as a driving cycle: the trainer can simulate the very inputs the firmware
// used (the golden test does). Estimates and health follow.
#pragma once

#include <cstdio>

#include "lptn/firmware/estimator.hpp"

namespace lptn::fw {

void write_estimate_header(std::FILE* out);
// time_s is counted from `t0_us` (the log's first frame).
void write_estimate_row(std::FILE* out, const EstimatorOutput<double>& o, TimeUs t0_us);

}  // namespace lptn::fw
