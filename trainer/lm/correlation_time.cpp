#include "trainer/lm/correlation_time.hpp"

#include <algorithm>
#include <bit>
#include <complex>
#include <unsupported/Eigen/FFT>

#include "hostio/worker_threads.hpp"

namespace lptn::lm {

std::vector<double> correlation_sums(const std::vector<std::vector<double>>& series, int threads) {
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
  // series zero-padded to twice its length has that sum as the inverse transform of |X|^2. The
  // series' transforms run in parallel (one FFT, with its cached plans, per thread) and are added
  // in the series' order, so the sums are the same bits whatever the threads.
  const std::size_t workers = std::clamp<std::size_t>(static_cast<std::size_t>(std::max(1, threads)), 1,
                                                      std::max<std::size_t>(1, series.size()));
  std::vector<Eigen::FFT<double>> ffts(workers);
  for (auto& fft : ffts) fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);
  std::vector<std::vector<double>> lag_products(series.size());
  hostio::parallel_for(series.size(), static_cast<int>(workers), [&](std::size_t i) {
    const std::vector<double>& r = series[i];
    if (r.size() < 2) return;
    Eigen::FFT<double>& fft = ffts[i % workers];  // parallel_for: item i on thread i mod workers
    const std::size_t n = std::bit_ceil(2 * r.size());
    std::vector<double> padded(n, 0.0), acf;
    std::vector<std::complex<double>> spectrum;
    std::copy(r.begin(), r.end(), padded.begin());
    fft.fwd(spectrum, padded);
    for (auto& x : spectrum) x = std::norm(x);
    fft.inv(acf, spectrum, static_cast<Eigen::Index>(n));
    // Only the lags summed are kept, in a vector of their size (a resized one would keep the
    // transform's whole capacity: 300 MB over a 200 h dump's series).
    const auto lags = static_cast<std::ptrdiff_t>(std::min(kMaxCorrelationLag, r.size()));
    lag_products[i].assign(acf.begin(), acf.begin() + lags);
  });
  for (std::size_t i = 0; i < series.size(); ++i) {
    const std::vector<double>& acf = lag_products[i];
    for (std::size_t lag = 1; lag < acf.size(); ++lag) {
      products[lag] += acf[lag];
      pairs[lag] += static_cast<double>(series[i].size() - lag);
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

double correlation_time(const std::vector<std::vector<double>>& series, int threads) {
  return correlation_time_of_sums(correlation_sums(series, threads));
}

}  // namespace lptn::lm
