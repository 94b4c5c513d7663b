// Motor constants with a value of its own in every member the field list names: a consumer that
// drops a member, or mixes two up, shows in a comparison with them.
#pragma once

#include <cstddef>
#include <type_traits>

#include "lptn/motor_constants.hpp"

namespace lptn::testing {

inline MotorConstants<double> distinct_motor_constants() {
  MotorConstants<double> c;
  int k = 0;
  int rows = 0;
  for_each_motor_constant(
      [&](const MotorField& f, auto& member) {
        using M = std::remove_reference_t<decltype(member)>;
        // Falling from field to field, so that a value that must stay below an earlier one does;
        // every value positive, and a multiple of 1/8 that float holds exactly.
        const double base = 1000.0 - 31.5 * ++k + 0.125;
        if constexpr (std::is_same_v<M, int>) {
          member = f.max_count - 1;  // neither the default nor the example motor's
          if (f.shape == FieldShape::table_size) rows = member;
        } else if constexpr (std::is_same_v<M, double>) {
          member = base;
        } else {
          // Increasing along the row; a table's rows beyond its size stay zero, as a reader leaves them.
          const std::size_t n = f.shape == FieldShape::table_column ? static_cast<std::size_t>(rows) : std::extent_v<M>;
          for (std::size_t i = 0; i < n; ++i) member[i] = base + 0.5 * static_cast<double>(i);
        }
      },
      c);
  return c;
}

}  // namespace lptn::testing
