// A sensor's noise, estimated from the model's residual rather than assumed: what tells a model
// error apart from the sensor's scatter, for the diagnosis's verdict on the model and the report.
#pragma once

#include <cstddef>
#include <vector>

#include "trainer/data/dataset.hpp"

namespace lptn::calibrate {

// A sensor's noise from the residual on the model's grid, where a sensor that reports every
// `period` steps is interpolated in between. At the steps where it reported, e_k - (e_{k-p} +
// e_{k+p})/2 has variance 1.5 s^2 for white noise of standard deviation s, and a slow model error
// (a missing effect) adds next to nothing to it; between those steps interpolation averages the
// noise away. The sample steps' phase is not known, so the phase (k mod period) with the largest
// mean square is taken. Sums, so that cycles pool: noise = sqrt(sum2 / n / 1.5).
struct NoiseSum {
  double sum2 = 0;
  std::size_t n = 0;
  NoiseSum& operator+=(const NoiseSum& o) {
    sum2 += o.sum2;
    n += o.n;
    return *this;
  }
  double sigma() const;  // NaN without a valid triple
};
NoiseSum sensor_noise(const std::vector<float>& e, std::size_t period);

// Grid steps per reading of channel `c` in `cycle`, from the loader's report on the cycle's file
// (1 where it has none: every step then counts as a reading).
std::size_t reading_period(const data::Dataset& dataset, const data::Cycle& cycle, data::Channel c);

}  // namespace lptn::calibrate
