#include "simulator/plant/gradient_profile.hpp"

namespace lptn::plant {

GradientProfile::GradientProfile(const RouteProfile& route, std::uint64_t seed)
    : route_(route), rng_(seed) {}

void GradientProfile::extend() {
  const double start = sections_.empty() ? 0.0 : sections_.back().end_m;
  const double length = rng_.uniform(route_.grade_section_m.lo, route_.grade_section_m.hi);
  double pct = 0.0;
  if (rng_.chance(route_.steep_grade_probability)) {
    if (!rng_.chance(route_.steep_sign_persistence)) last_steep_sign_ = -last_steep_sign_;
    pct = last_steep_sign_ * rng_.uniform(route_.steep_grade_pct.lo, route_.steep_grade_pct.hi);
  } else {
    pct = rng_.uniform(-route_.mild_grade_pct, route_.mild_grade_pct);
  }
  sections_.push_back({start + length, pct / 100.0});
}

double GradientProfile::grade_at(double distance_m) {
  while (sections_.empty() || sections_.back().end_m <= distance_m) extend();
  if (cursor_ >= sections_.size()) cursor_ = 0;
  if (cursor_ > 0 && sections_[cursor_ - 1].end_m > distance_m) cursor_ = 0;
  while (sections_[cursor_].end_m <= distance_m) ++cursor_;
  return sections_[cursor_].grade;
}

}  // namespace lptn::plant
