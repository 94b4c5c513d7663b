// Student's t distribution: what the fleet's outlier test compares with.
#pragma once

namespace lptn::fleet::internal {

// P(T <= t) for T ~ Student's t with `dof` degrees of freedom (dof > 0).
double student_t_cdf(double t, double dof);
// The t with student_t_cdf(t, dof) = p, 0 < p < 1.
double student_t_quantile(double p, double dof);

}  // namespace lptn::fleet::internal
