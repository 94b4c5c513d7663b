// Two sets of error metrics equal to the bit (EXPECT_EQ on doubles: equal, not close): for figures
// that two routes must compute alike (a calibration file written and read back; the metrics
// compared as the model runs and over a stored simulation).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "trainer/model/simulate.hpp"

namespace lptn::testing {

inline void expect_same_metrics(const model::ErrorMetrics& a, const model::ErrorMetrics& b, const std::string& what) {
  EXPECT_EQ(a.rmse_k, b.rmse_k) << what;
  EXPECT_EQ(a.mean_abs_k, b.mean_abs_k) << what;
  EXPECT_EQ(a.max_abs_k, b.max_abs_k) << what;
  EXPECT_EQ(a.bias_k, b.bias_k) << what;
  EXPECT_EQ(a.samples, b.samples) << what;
}

}  // namespace lptn::testing
