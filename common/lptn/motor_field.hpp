// How one of the motor's constants appears in the motor file (TOML) and in the exported firmware
// header, and what the motor file's reader demands of it. The lists of fields are nameplate.hpp's
// (the nameplate) and motor_constant_fields.hpp's (all of MotorConstants); the reader, the writer,
// the exporter and MotorConstants::cast() walk those lists instead of naming the members again.
#pragma once

#include <string_view>

#include "lptn/heat_balance.hpp"

namespace lptn {

// What the member is, which decides how each consumer reads, writes and copies it.
enum class FieldShape {
  integer,       // int, one key holding a whole number from 1 to max_count
  scalar,        // R, one key
  table_size,    // int with no key of its own: the rows of the `columns` table_column fields after it
  table_column,  // R[N], one key holding an array of that table's rows (1 to max_count of them)
  per_node,      // R[kNumNodes], one key per thermal node (node_keys)
};

// What the motor file's reader demands of each value; the reason in brackets is what it says.
enum class FieldRule {
  finite,        // any finite number (every value must be one)
  positive,      // "must be greater than zero"
  non_negative,  // "must not be negative"
  increasing,    // table_column: "must increase strictly" from row to row
};

struct MotorField {
  std::string_view section = {};  // the motor file's table: nameplate, electrical, losses or thermal
  std::string_view name = {};     // the member, and its key in the motor file (per_node: see node_keys)
  FieldShape shape = FieldShape::scalar;
  FieldRule rule = FieldRule::positive;
  bool required = true;     // false: a file without the key keeps the member's default
  int max_count = 0;        // integer: the largest value; table_size: the most rows
  int columns = 0;          // table_size: how many table_column fields follow it
  std::string_view below = {};   // "section.key" of a value read earlier that this one must stay below
  std::string_view note = {};    // the comment the motor file's writer puts after the value
  int note_gap = 0;         // spaces before that comment (they line up as in docs/motor.example.toml)
  std::string_view node_keys[kNumNodes] = {};   // per_node: each node's key, in node order
  std::string_view node_names[kNumNodes] = {};  // per_node: each node, for the exported header's comments
};

}  // namespace lptn
