// The statistics behind `lptn report`'s "Where it fails" section: binning of residuals by operating
// region, the worst time windows, correlations with confidence bands, and the min/mean/max
// envelopes that keep hours of 10 Hz data small enough for a browser. Plain numbers in, plain
// numbers out (NaN = missing), so each piece is testable on its own.
#pragma once

#include <cstddef>
#include <vector>

namespace lptn::report {

// One series split into segments (one per cycle): lags never reach across a segment's end.
using Segments = std::vector<std::vector<double>>;

// Means over consecutive blocks of `block` samples (NaN where a block has no valid sample).
std::vector<double> block_means(const std::vector<float>& samples, std::size_t block);

// Min, mean and max of each bucket of consecutive samples.
struct Envelope {
  std::vector<double> lo, mean, hi;
};
Envelope envelope(const std::vector<float>& samples, std::size_t bucket);

// r(k) = sum (e_t - mean)(e_{t+k} - mean) / sum (e_t - mean)^2 for k = 0..max_lag, sums over
// the pairs inside one segment where both are valid.
std::vector<double> autocorrelation(const Segments& e, std::size_t max_lag);

// corr(x_t, e_{t+k}) for k = -max_lag..max_lag (index k + max_lag): a positive lag means the
// residual follows the input. Pairs as in autocorrelation.
std::vector<double> cross_correlation(const Segments& x, const Segments& e, std::size_t max_lag);

// Valid samples (not NaN) over all segments.
std::size_t valid_count(const Segments& e);

// Root mean square of the valid samples over all segments (NaN when there is none).
double rms(const Segments& e);

// 95 % band of an autocorrelation under the hypothesis of white residuals: 1.96 / sqrt(n).
double white_noise_band(std::size_t n);
// 95 % band of a cross-correlation of two series that are each autocorrelated but independent of
// each other (Bartlett): 1.96 sqrt(sum_k rx(k) re(k) / n) over |k| <= max lag, never narrower
// than the white-noise band. Without the correction slow inputs against slow residuals would
// show "significant" correlation at every lag.
double bartlett_band(std::size_t n, const std::vector<double>& acf_x, const std::vector<double>& acf_e);

// Residual statistics of the samples whose value falls into one bin.
struct Bin {
  double lo = 0, hi = 0;
  std::size_t n = 0;
  double mean = 0, rmse = 0;
};
// `edges` ascending, at least two; values below the first edge count in the first bin and values
// above the last in the last, so that every valid pair is counted exactly once.
std::vector<Bin> bin_residuals(const std::vector<double>& x, const std::vector<double>& e,
                               const std::vector<double>& edges);
// The same over two variables: result[i][j] for x bin i and y bin j.
std::vector<std::vector<Bin>> bin_residuals_2d(const std::vector<double>& x, const std::vector<double>& y,
                                               const std::vector<double>& e, const std::vector<double>& x_edges,
                                               const std::vector<double>& y_edges);
// `count` equal bins over [lo, hi] (hi > lo enforced by widening a degenerate range).
std::vector<double> linear_edges(double lo, double hi, std::size_t count);
// Bins of width `step` aligned on multiples of it, covering [lo, hi].
std::vector<double> aligned_edges(double lo, double hi, double step);
// Edges at the quantiles of x (valid values; duplicates removed, so possibly fewer bins).
std::vector<double> quantile_edges(const std::vector<double>& x, std::size_t count);

// The window of `length` samples with the largest RMSE, the next one not overlapping it, ...
struct Window {
  std::size_t segment = 0;
  std::size_t start = 0, length = 0;  // samples into the segment
  double rmse = 0;
  std::size_t n = 0;  // valid samples in it
};
// Candidates start every `stride` samples and need half their samples valid. Sorted by RMSE,
// largest first; no two overlap.
std::vector<Window> worst_windows(const Segments& e, std::size_t length, std::size_t stride, std::size_t count);

// Min and max of the valid values (NaN, NaN when there is none).
struct Range {
  double lo, hi;
};
Range valid_range(const std::vector<double>& x);

}  // namespace lptn::report
