// Which motors of a fleet cool unlike the others: a leave-one-out prediction test on the motors'
// log cooling factors.
//
// For motor m of n, with the other n - 1 motors' log factors of mean x and standard deviation s
// (which hold the fleet's true spread and the others' own estimation errors), the motor's log
// factor y is predicted from them with variance s^2 (1 + 1/(n-1)) plus whatever its own error
// exceeds theirs by (a motor with little data). The statistic
//     t = (y - x) / sqrt(s^2 (1 + 1/(n-1)) + max(0, se_m^2 - mean of the others' se^2))
// is Student's t with n - 2 degrees of freedom when every motor's log factor is drawn from one
// normal distribution (the fleet has no outlier). A motor is an outlier when |t| exceeds the
// two-sided quantile at family_alpha / n (Bonferroni): the chance that a fleet without outliers
// names any motor is then at most family_alpha (measured in tests/fleet). Leave-one-out keeps an
// outlier from widening the spread it is judged by; two outliers alike can still mask each other.
#pragma once

#include <string>
#include <vector>

namespace lptn::fleet {

inline constexpr int kMinMotorsForOutlierTest = 4;  // n - 2 >= 2 degrees of freedom

struct MotorFactor {
  double log_factor = 0;
  double log_std_error = 0;
};

struct OutlierVerdict {
  bool tested = false;  // false with fewer than kMinMotorsForOutlierTest motors
  bool outlier = false;
  double t = 0;
  double threshold = 0;  // |t| beyond this is an outlier
  std::string reason;    // one line, in words
};

std::vector<OutlierVerdict> fleet_outliers(const std::vector<MotorFactor>& motors, double family_alpha);

// The median of `values` (of an even count, the mean of the two middle ones): the fleet's median
// motor, which the fit normalizes to and the verdicts compare with.
double median(std::vector<double> values);

// The |t| beyond which a fleet of `motors` motors names an outlier.
double outlier_threshold(int motors, double family_alpha);

}  // namespace lptn::fleet
