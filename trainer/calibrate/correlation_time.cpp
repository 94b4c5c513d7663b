#include "trainer/calibrate/correlation_time.hpp"

#include <algorithm>
#include <bit>
#include <complex>
#include <unsupported/Eigen/FFT>

namespace lptn {

double correlation_time(const std::vector<std::vector<double>>& series) {
  double var = 0, count = 0;
  for (const auto& r : series)
    for (double e : r) {
      var += e * e;
      count += 1;
    }
  if (count < 2 || var <= 0) return 1.0;
  var /= count;

  // Per lag: the sum of r[k] r[k - lag] over every series, and how many products it holds. A
  // series zero-padded to twice its length has that sum as the inverse transform of |X|^2.
  std::vector<double> products(kMaxCorrelationLag, 0.0), pairs(kMaxCorrelationLag, 0.0);
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
  double tau = 1.0;
  for (std::size_t lag = 1; lag < kMaxCorrelationLag; ++lag) {
    if (pairs[lag] < 100) break;
    const double rho = products[lag] / pairs[lag] / var;
    if (rho <= 0) break;
    tau += 2 * rho;
  }
  return tau;
}

}  // namespace lptn
