// Every member of MotorConstants with its place in the motor file: the one list that the motor
// file's reader and writer, the firmware header's exporter and MotorConstants::cast() walk. A
// member added to MotorConstants goes here too (tests/common/test_motor_constant_fields.cpp fails
// otherwise), and then every one of them handles it.
#pragma once

#include "lptn/motor_field.hpp"
#include "lptn/nameplate.hpp"

namespace lptn {

inline constexpr int kMaxHarmonicPoints = 16;

// Calls f(field, c.member...) for every member of the constants c (MotorConstants of any scalar,
// all alike), in the motor file's order: section by section, keys as the writer writes them.
template <class F, class... C>
constexpr void for_each_motor_constant(F&& f, C&... c) {
  using S = FieldShape;
  using Rule = FieldRule;
  for_each_nameplate_field(f, c...);

  f(MotorField{.section = "electrical", .name = "stator_resistance_20c_ohm", .note = "per phase", .note_gap = 2},
    c.stator_resistance_20c_ohm...);
  f(MotorField{.section = "electrical", .name = "stator_resistance_alpha_per_k", .rule = Rule::finite},
    c.stator_resistance_alpha_per_k...);
  f(MotorField{.section = "electrical",
               .name = "rotor_resistance_20c_ohm",
               .note = "referred to the stator",
               .note_gap = 3},
    c.rotor_resistance_20c_ohm...);
  f(MotorField{.section = "electrical", .name = "rotor_resistance_alpha_per_k", .rule = Rule::finite},
    c.rotor_resistance_alpha_per_k...);
  // Below the rated current: the model's rotor current is I21^2 = I1^2 - Im^2 (eq. 9).
  f(MotorField{.section = "electrical",
               .name = "magnetizing_current_a",
               .below = "nameplate.rated_current_a",
               .note = "at rated flux",
               .note_gap = 6},
    c.magnetizing_current_a...);

  f(MotorField{.section = "losses", .name = "stray_rated_w", .rule = Rule::non_negative}, c.stray_rated_w...);
  f(MotorField{.section = "losses", .name = "iron_rated_w", .rule = Rule::non_negative}, c.iron_rated_w...);
  f(MotorField{.section = "losses", .name = "iron_alpha"}, c.iron_alpha...);
  f(MotorField{.section = "losses", .name = "iron_beta"}, c.iron_beta...);
  // Eq. 13's look-up table over stator frequency: two columns of harmonic_points rows.
  f(MotorField{.section = "losses", .name = "harmonic_points", .shape = S::table_size, .max_count = kMaxHarmonicPoints,
               .columns = 2},
    c.harmonic_points...);
  f(MotorField{.section = "losses",
               .name = "harmonic_frequency_hz",
               .shape = S::table_column,
               .rule = Rule::increasing},
    c.harmonic_frequency_hz...);
  f(MotorField{.section = "losses", .name = "harmonic_loss_w", .shape = S::table_column, .rule = Rule::non_negative},
    c.harmonic_loss_w...);

  f(MotorField{.section = "thermal",
               .name = "capacitance_j_per_k",
               .shape = S::per_node,
               .node_keys = {"capacitance_stator_winding_j_per_k", "capacitance_stator_core_j_per_k",
                             "capacitance_rotor_winding_j_per_k", "capacitance_rotor_core_j_per_k"},
               .node_names = {"stator winding", "stator core", "rotor winding", "rotor core"}},
    c.capacitance_j_per_k...);
  f(MotorField{.section = "thermal", .name = "nominal_airflow_m3s"}, c.nominal_airflow_m3s...);
  f(MotorField{.section = "thermal", .name = "airflow_exponent"}, c.airflow_exponent...);
  f(MotorField{.section = "thermal", .name = "min_airflow_fraction", .required = false}, c.min_airflow_fraction...);
}

}  // namespace lptn
