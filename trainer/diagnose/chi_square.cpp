// The chi-square quantile the likelihood-ratio test compares with, without a statistics library.
#include <cmath>
#include <stdexcept>

#include "trainer/diagnose/diagnose.hpp"

namespace lptn::diagnose {
namespace {

// The standard normal p-quantile: Acklam's rational approximation (relative error < 1.2e-9),
// refined by one Halley step on erfc.
double normal_quantile(double p) {
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                                 1.383577518672690e+02, -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                                 6.680131188771972e+01, -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                                 -2.549732539343734e+00, 4.374664141464968e+00, 2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                                 3.754408661907416e+00};
  constexpr double low = 0.02425;
  double x;
  if (p < low) {
    const double q = std::sqrt(-2 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  } else if (p <= 1 - low) {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
  } else {
    const double q = std::sqrt(-2 * std::log(1 - p));
    x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  }
  const double e = 0.5 * std::erfc(-x / std::sqrt(2.0)) - p;
  const double u = e * std::sqrt(2 * M_PI) * std::exp(x * x / 2);
  return x - u / (1 + x * u / 2);
}

}  // namespace

double student_t_quantile(double p, int df) {
  if (!(p > 0.5 && p < 1) || df < 1) throw std::invalid_argument("student_t_quantile: needs 0.5 < p < 1 and df >= 1");
  if (df == 1) return std::tan(M_PI * (p - 0.5));  // Cauchy
  if (df == 2) {
    const double a = 4 * p * (1 - p);
    return 2 * (p - 0.5) * std::sqrt(2 / a);
  }
  // Cornish-Fisher expansion about the normal quantile (Abramowitz & Stegun 26.7.5): within 3 %
  // at df 3 and p = 0.999, far closer above.
  const double z = normal_quantile(p), v = df;
  const double z2 = z * z, z3 = z2 * z, z5 = z3 * z2, z7 = z5 * z2, z9 = z7 * z2;
  const double g1 = (z3 + z) / 4, g2 = (5 * z5 + 16 * z3 + 3 * z) / 96,
               g3 = (3 * z7 + 19 * z5 + 17 * z3 - 15 * z) / 384,
               g4 = (79 * z9 + 776 * z7 + 1482 * z5 - 1920 * z3 - 945 * z) / 92160;
  return z + g1 / v + g2 / (v * v) + g3 / (v * v * v) + g4 / (v * v * v * v);
}

double chi_square_quantile(double p, int df) {
  if (!(p > 0 && p < 1) || df < 1) throw std::invalid_argument("chi_square_quantile: needs 0 < p < 1 and df >= 1");
  if (df == 1) {
    const double z = normal_quantile(0.5 + p / 2);  // chi2(1) is z^2
    return z * z;
  }
  if (df == 2) return -2 * std::log(1 - p);  // chi2(2) is exponential with mean 2
  const double k = df, h = 2.0 / (9.0 * k);
  const double cube = 1 - h + normal_quantile(p) * std::sqrt(h);
  return k * cube * cube * cube;
}

}  // namespace lptn::diagnose
