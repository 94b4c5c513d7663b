// CMA-ES on functions whose minimum is known: it must find it, with the tutorial's defaults,
// where the problem is badly scaled and rotated (what the covariance is for).
#include <gtest/gtest.h>

#include <cmath>

#include "trainer/search/internal/cma_es.hpp"

namespace lptn::search {
namespace {

// An ellipsoid with axes 1 .. 1e3 apart, rotated by 45 degrees in each pair of coordinates.
double ellipsoid(const double* x, std::size_t n) {
  double f = 0;
  for (std::size_t i = 0; i + 1 < n; i += 2) {
    const double a = (x[i] + x[i + 1] - 1.0) / std::sqrt(2.0), b = (x[i] - x[i + 1]) / std::sqrt(2.0);
    const double wa = std::pow(1e3, double(i) / double(n - 1)), wb = std::pow(1e3, double(i + 1) / double(n - 1));
    f += wa * wa * a * a + wb * wb * b * b;
  }
  return f;
}

TEST(CmaEs, FindsTheMinimumOfARotatedIllConditionedEllipsoid) {
  const std::size_t n = 6;
  CmaEs cma(std::vector<double>(n, 3.0), 1.0, 7);
  EXPECT_EQ(cma.lambda(), 4 + static_cast<int>(std::floor(3 * std::log(6.0))));
  double best = 1e300;
  int generations = 0;
  for (; generations < 2000 && best > 1e-12; ++generations) {
    const std::vector<double> x = cma.ask();
    std::vector<double> f;
    for (int k = 0; k < cma.lambda(); ++k) f.push_back(ellipsoid(x.data() + k * n, n));
    for (double v : f) best = std::min(best, v);
    cma.tell(f);
  }
  std::printf("%d generations to f = %.2e\n", generations, best);
  EXPECT_LE(best, 1e-12);
  EXPECT_LT(generations, 1000);  // a step size that did not adapt would need far more
  for (std::size_t i = 0; i < n; ++i) EXPECT_NEAR(cma.mean()[i], 0.5, 1e-4) << i;
}

TEST(CmaEs, TheSameSeedGivesTheSameSearch) {
  CmaEs a({1.0, 2.0}, 0.5, 3), b({1.0, 2.0}, 0.5, 3);
  for (int g = 0; g < 5; ++g) {
    const std::vector<double> xa = a.ask(), xb = b.ask();
    EXPECT_EQ(xa, xb);
    std::vector<double> f;
    for (int k = 0; k < a.lambda(); ++k) f.push_back(xa[2 * k] * xa[2 * k] + xa[2 * k + 1] * xa[2 * k + 1]);
    a.tell(f);
    b.tell(f);
  }
  EXPECT_THROW(a.tell({1.0}), std::invalid_argument);
  EXPECT_THROW(CmaEs({}, 1.0, 1), std::invalid_argument);
}

}  // namespace
}  // namespace lptn::search
