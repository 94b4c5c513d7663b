// A motor as JSON: what calibration.json carries (format 3 on), so that a calibration rebuilds its
// model without parsing TOML. The same sections and keys as the motor file (docs/model.md, "The
// motor file"), walked from the same field lists and read back by the same rules; the parameters
// the file sets, and its effects. The file's own text travels beside it as provenance only.
#pragma once

#include <nlohmann/json.hpp>

#include "hostio/json_file.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::model {

// {"name", "constants": {SECTION: {KEY: value}}, "parameters": {NAME: {initial, min, max,
// calibrate}} (the ones the file sets), "effects": [NAME]}. Neither the path nor the text.
nlohmann::ordered_json motor_json(const MotorFile& motor);

// The motor `motor_json` wrote (path and text left empty); throws JsonFileError naming the field
// ("cal.json: field 'motor.constants.thermal.mass_stator_kg': must be greater than zero").
MotorFile motor_from_json(const hostio::JsonField& motor);

}  // namespace lptn::model
