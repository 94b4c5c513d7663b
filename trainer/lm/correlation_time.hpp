// How many residuals carry the information of one independent one.
#pragma once

#include <cstddef>
#include <vector>

namespace lptn::lm {

// 1 + 2 sum rho_k over the residuals' autocorrelation (pooled over the series, each demeaned by
// the caller), summed while it stays positive (Geyer's initial positive sequence) and up to
// kMaxCorrelationLag lags. Sensors read at 1 Hz are interpolated onto the 10 Hz grid, and a model
// that is not quite right leaves slow residual structure; both make J^T J count the same
// information many times. The autocorrelation comes from FFTs of each series, so the cost is
// linear in the data whatever the lag at which the sum stops.
inline constexpr std::size_t kMaxCorrelationLag = 6000;  // ten minutes at 10 Hz

// `threads`: the series' transforms run over that many threads; the result does not depend on it.
double correlation_time(const std::vector<std::vector<double>>& series, int threads = 1);

// The same in two halves, for series spread over processes: the sums over this process's series
// (the residuals' square sum and count, then per lag the sum of products and their number), which
// add element by element over processes, and the correlation time of the added sums.
std::vector<double> correlation_sums(const std::vector<std::vector<double>>& series, int threads = 1);
double correlation_time_of_sums(const std::vector<double>& sums);

}  // namespace lptn::lm
