// What a motor the readers accepted must hold, whichever form it came in (fuzz_motor_toml: the
// motor file; fuzz_motor_json: its copy in calibration.json): what the readers promise to check.
#pragma once

#include <cmath>
#include <cstddef>

#include "fuzz_check.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::model {

inline void check_motor(const model::MotorFile& m) {
  const MotorConstants<double>& c = m.constants;
  LPTN_FUZZ_CHECK(c.pole_pairs >= 1 && c.pole_pairs <= 16, "pole pairs");
  for (double v : {c.rated_frequency_hz, c.rated_voltage_v, c.rated_current_a, c.rated_power_w,
                   c.stator_resistance_20c_ohm, c.rotor_resistance_20c_ohm, c.magnetizing_current_a, c.iron_alpha,
                   c.iron_beta, c.nominal_airflow_m3s, c.airflow_exponent, c.min_airflow_fraction})
    LPTN_FUZZ_CHECK(std::isfinite(v) && v > 0, "a constant that must be positive");
  LPTN_FUZZ_CHECK(c.magnetizing_current_a < c.rated_current_a, "magnetizing current below rated");
  LPTN_FUZZ_CHECK(c.stray_rated_w >= 0 && c.iron_rated_w >= 0, "losses");
  LPTN_FUZZ_CHECK(c.harmonic_points >= 1 && c.harmonic_points <= kMaxHarmonicPoints, "harmonic table size");
  for (int i = 0; i < c.harmonic_points; ++i) {
    LPTN_FUZZ_CHECK(i == 0 || c.harmonic_frequency_hz[i] > c.harmonic_frequency_hz[i - 1], "harmonic frequencies");
    LPTN_FUZZ_CHECK(c.harmonic_loss_w[i] >= 0, "harmonic losses");
  }
  for (double cap : c.capacitance_j_per_k) LPTN_FUZZ_CHECK(std::isfinite(cap) && cap > 0, "capacitance");
  for (int i = 0; i < kNumParams; ++i) {
    const model::ParameterSetting& s = m.parameters[static_cast<std::size_t>(i)];
    LPTN_FUZZ_CHECK(std::isfinite(s.min) && std::isfinite(s.max) && std::isfinite(s.initial), param_spec(i).name.data());
    LPTN_FUZZ_CHECK(s.min < s.max && s.initial >= s.min && s.initial <= s.max, param_spec(i).name.data());
  }
  LPTN_FUZZ_CHECK((m.effects & ~((EffectSet{1} << kNumEffects) - 1)) == 0, "an effect bit beyond the library");
  (void)m.model();  // the model takes whatever the reader accepted
}

}  // namespace lptn::model
