#include "trainer/fleet/outlier_test.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "trainer/fleet/internal/student_t.hpp"

namespace lptn::fleet {

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double outlier_threshold(int motors, double family_alpha) {
  return internal::student_t_quantile(1 - family_alpha / (2.0 * motors), motors - 2.0);
}

std::vector<OutlierVerdict> fleet_outliers(const std::vector<MotorFactor>& motors, double family_alpha) {
  const int n = static_cast<int>(motors.size());
  std::vector<OutlierVerdict> out(motors.size());
  if (n < kMinMotorsForOutlierTest) {
    for (OutlierVerdict& v : out)
      v.reason = "not tested: " + std::to_string(n) + " motors are too few to tell a fleet's spread (the test needs " +
                 std::to_string(kMinMotorsForOutlierTest) + ")";
    return out;
  }
  const double threshold = outlier_threshold(n, family_alpha);
  // In words, a motor is compared with the fleet's median motor (the type, once normalized).
  std::vector<double> logs;
  for (const MotorFactor& f : motors) logs.push_back(f.log_factor);
  const double fleet_median = median(logs);
  for (int m = 0; m < n; ++m) {
    double mean = 0, own_var = 0;
    for (int j = 0; j < n; ++j)
      if (j != m) {
        mean += motors[static_cast<std::size_t>(j)].log_factor;
        own_var += motors[static_cast<std::size_t>(j)].log_std_error * motors[static_cast<std::size_t>(j)].log_std_error;
      }
    mean /= n - 1;
    own_var /= n - 1;
    double ss = 0;
    for (int j = 0; j < n; ++j)
      if (j != m) ss += std::pow(motors[static_cast<std::size_t>(j)].log_factor - mean, 2);
    const double s2 = ss / (n - 2);
    const MotorFactor& me = motors[static_cast<std::size_t>(m)];
    const double extra = std::max(0.0, me.log_std_error * me.log_std_error - own_var);
    const double se = std::sqrt(s2 * (1 + 1.0 / (n - 1)) + extra);
    const double diff = me.log_factor - mean;
    OutlierVerdict& v = out[static_cast<std::size_t>(m)];
    v.tested = true;
    v.threshold = threshold;
    v.t = se > 0 ? diff / se : (diff == 0 ? 0.0 : std::copysign(std::numeric_limits<double>::infinity(), diff));
    v.outlier = std::abs(v.t) > threshold;
    // To the 0.1 % the words show, and never "-0.0 %".
    double percent = std::round(1000 * (std::exp(me.log_factor - fleet_median) - 1)) / 10;
    if (percent == 0) percent = 0;
    char buf[200];
    if (v.outlier)
      std::snprintf(buf, sizeof buf, "cools %.0f %% %s than the fleet's median motor, beyond the others' spread (t = %+.1f, limit +-%.1f)",
                    std::abs(percent), percent < 0 ? "worse" : "better", v.t, threshold);
    else
      std::snprintf(buf, sizeof buf, "within the others' spread (%+.1f %% from the fleet's median motor, t = %+.1f, limit +-%.1f)",
                    percent, v.t, threshold);
    v.reason = buf;
  }
  return out;
}

}  // namespace lptn::fleet
