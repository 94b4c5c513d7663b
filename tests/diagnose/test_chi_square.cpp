// The chi-square quantile the likelihood-ratio test compares with, against tabulated values.
#include <gtest/gtest.h>

#include <stdexcept>

#include "trainer/diagnose/diagnose.hpp"

namespace lptn::diagnose {
namespace {

TEST(ChiSquareQuantile, IsExactForOneAndTwoDegreesOfFreedom) {
  EXPECT_NEAR(chi_square_quantile(0.95, 1), 3.841459, 1e-5);
  EXPECT_NEAR(chi_square_quantile(0.999, 1), 10.827566, 1e-5);
  EXPECT_NEAR(chi_square_quantile(0.5, 1), 0.454936, 1e-5);
  EXPECT_NEAR(chi_square_quantile(0.95, 2), 5.991465, 1e-5);
  EXPECT_NEAR(chi_square_quantile(0.999, 2), 13.815511, 1e-5);
}

// Wilson-Hilferty is within 2 %, and at p = 0.999 (diagnose's level) high: a conservative threshold.
TEST(ChiSquareQuantile, WilsonHilfertyIsWithinTwoPercentAndConservativeAtTheTestLevel) {
  const struct {
    double p;
    int df;
    double table;
  } cases[] = {{0.95, 3, 7.814728}, {0.999, 3, 16.266236}, {0.999, 5, 20.515006}, {0.95, 10, 18.307038},
               {0.999, 10, 29.588298}, {0.5, 4, 3.356694}, {0.99, 30, 50.892181}};
  for (const auto& c : cases) {
    const double q = chi_square_quantile(c.p, c.df);
    EXPECT_NEAR(q / c.table, 1.0, 0.02) << c.p << " " << c.df;
    if (c.p == 0.999) {
      EXPECT_GE(q, c.table) << c.df;
    }
  }
}

TEST(ChiSquareQuantile, RefusesWhatIsNotADistribution) {
  EXPECT_THROW(chi_square_quantile(1.0, 1), std::invalid_argument);
  EXPECT_THROW(chi_square_quantile(0.9, 0), std::invalid_argument);
}

}  // namespace
}  // namespace lptn::diagnose
