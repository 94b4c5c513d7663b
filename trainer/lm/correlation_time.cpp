#include "trainer/lm/correlation_time.hpp"

#include <algorithm>
#include <bit>
#include <complex>
#include <unsupported/Eigen/FFT>

namespace lptn {

std::vector<double> correlation_sums(const std::vector<std::vector<double>>& series) {
  // [0] sum of squares, [1] count, [2 + lag] products at lag, [2 + kMaxCorrelationLag + lag] pairs.
  std::vector<double> sums(2 + 2 * kMaxCorrelationLag, 0.0);
  double* products = sums.data() + 2;
  double* pairs = products + kMaxCorrelationLag;
  for (const auto& r : series)
    for (double e : r) {
      sums[0] += e * e;
      sums[1] += 1;
    }
  // Per lag: the sum of r[k] r[k - lag] over every series, and how many products it holds. A
  // series zero-padded to twice its length has that sum as the inverse transform of |X|^2.
  Eigen::FFT<double> fft;
  fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);
  std::vector<double> padded, acf;
  std::vector<std::complex<double>> spectrum;
  for (const auto& r : series) {
    if (r.size() < 2) continue;
    const std::size_t n = std::bit_ceil(2 * r.size());
    padded.assign(n, 0.0);
    std::copy(r.begin(), r.end(), padded.begin());
    fft.fwd(spectrum, padded);
    for (auto& x : spectrum) x = std::norm(x);
    fft.inv(acf, spectrum, static_cast<Eigen::Index>(n));
    const std::size_t lags = std::min(kMaxCorrelationLag, r.size());
    for (std::size_t lag = 1; lag < lags; ++lag) {
      products[lag] += acf[lag];
      pairs[lag] += static_cast<double>(r.size() - lag);
    }
  }
  return sums;
}

double correlation_time_of_sums(const std::vector<double>& sums) {
  const double count = sums[1];
  if (count < 2 || sums[0] <= 0) return 1.0;
  const double var = sums[0] / count;
  const double* products = sums.data() + 2;
  const double* pairs = products + kMaxCorrelationLag;
  double tau = 1.0;
  for (std::size_t lag = 1; lag < kMaxCorrelationLag; ++lag) {
    if (pairs[lag] < 100) break;
    const double rho = products[lag] / pairs[lag] / var;
    if (rho <= 0) break;
    tau += 2 * rho;
  }
  return tau;
}

double correlation_time(const std::vector<std::vector<double>>& series) {
  return correlation_time_of_sums(correlation_sums(series));
}

}  // namespace lptn
