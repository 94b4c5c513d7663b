// What the user knows about the motor from nameplate, geometry and bench tests: the constants of
// the paper's loss model and thermal network that calibration does not move. Each member's section
// and key in the motor file, its rule and its note are in motor_constant_fields.hpp, the list that
// every consumer walks.
#pragma once

#include <cstddef>
#include <type_traits>

#include "lptn/motor_constant_fields.hpp"
#include "lptn/nameplate.hpp"

namespace lptn {

namespace internal {
template <class To, class From>
constexpr void cast_member(To& to, const From& from) {
  if constexpr (std::is_array_v<To>) {
    for (std::size_t i = 0; i < std::extent_v<To>; ++i) to[i] = std::remove_extent_t<To>(from[i]);
  } else {
    to = To(from);
  }
}
}  // namespace internal

template <class R>
struct MotorConstants : Nameplate<R> {
  R stator_resistance_20c_ohm = R(0.14);
  R stator_resistance_alpha_per_k = R(0.00393);
  R rotor_resistance_20c_ohm = R(0.10);
  R rotor_resistance_alpha_per_k = R(0.0039);
  R magnetizing_current_a = R(40);

  R stray_rated_w = R(1400);  // eq. 11 at rated frequency and current
  R iron_rated_w = R(2800);   // eq. 12 at rated frequency and flux
  R iron_alpha = R(1.5);
  R iron_beta = R(2.0);
  int harmonic_points = 0;  // eq. 13's look-up table over stator frequency
  R harmonic_frequency_hz[kMaxHarmonicPoints] = {};
  R harmonic_loss_w[kMaxHarmonicPoints] = {};

  R capacitance_j_per_k[kNumNodes] = {R(38e3), R(240e3), R(22e3), R(110e3)};
  R nominal_airflow_m3s = R(1);
  R airflow_exponent = R(0.8);
  // Natural convection keeps some cooling when the blower stops; without a floor the conductances
  // to the air would vanish with the airflow and a standing motor could never cool.
  R min_airflow_fraction = R(0.1);

  template <class To>
  MotorConstants<To> cast() const {
    MotorConstants<To> c;
    for_each_motor_constant([](const MotorField&, auto& to, const auto& from) { internal::cast_member(to, from); }, c,
                            *this);
    return c;
  }
};

}  // namespace lptn
