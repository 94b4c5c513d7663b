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

// The block test's threshold (internal/block_test.hpp), against tabulated Student t quantiles.
namespace lptn::diagnose {
namespace {

TEST(StudentTQuantile, MatchesTablesWhereTheBlockTestUsesIt) {
  EXPECT_NEAR(student_t_quantile(0.975, 1), 12.7062, 1e-3);
  EXPECT_NEAR(student_t_quantile(0.975, 2), 4.3027, 1e-3);
  EXPECT_NEAR(student_t_quantile(0.975, 10), 2.2281, 2e-3);
  EXPECT_NEAR(student_t_quantile(0.999, 9), 4.2968, 0.02 * 4.2968);
  EXPECT_NEAR(student_t_quantile(0.999, 23), 3.4850, 0.005 * 3.4850);
  EXPECT_NEAR(student_t_quantile(0.999, 3), 10.2145, 0.03 * 10.2145);
  EXPECT_THROW(student_t_quantile(0.4, 5), std::invalid_argument);
}

}  // namespace
}  // namespace lptn::diagnose
