// What a motor's description must satisfy, whichever form it comes in: the motor file (TOML,
// motor_file.cpp) or its copy in a calibration (JSON, motor_json.cpp). Both readers walk the same
// field lists and ask these, so a value one refuses the other refuses with the same words.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "lptn/model.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::model::internal {

// The motor file's sections that hold constants, in the order of their list.
std::vector<std::string_view> constant_sections();

// What `rule` says about v (the previous row's value given for a table column), or nullptr.
const char* rule_broken(FieldRule rule, double v, const double* previous);

// The constant `full_key` ("section.key") as read so far (a field's `below`).
double constant_named(const MotorConstants<double>& c, std::string_view full_key);

// What is wrong with a parameter's settings, or nothing (reason empty). `at` is the key the
// complaint points at (min, max or initial); `key` the one it names ("" for the parameter itself).
struct SettingProblem {
  std::string_view at, key;
  std::string reason;
};
SettingProblem setting_problem(int index, const ParameterSetting& s);

}  // namespace lptn::model::internal
