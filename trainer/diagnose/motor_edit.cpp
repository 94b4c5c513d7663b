// The motor a diagnosis works on: effects by name, switched on, and the model a calibration used.
#include <stdexcept>
#include <string>

#include "trainer/diagnose/diagnose.hpp"

namespace lptn::diagnose {

int effect_by_name(std::string_view name, std::string_view option) {
  const int e = effect_index(name);
  if (e >= 0) return e;
  std::string known;
  for (std::string_view n : EffectLibrary::kNames) known += (known.empty() ? "" : ", ") + std::string(n);
  throw std::invalid_argument(std::string(option) + ": unknown effect '" + std::string(name) + "' (known: " + known + ")");
}

void enable_effect(MotorFile& motor, int effect) {
  motor.effects |= effect_bit(effect);
  // A parameter the file sets keeps the user's setting; the others take the library's.
  const std::array<ParameterSetting, kNumParams> defaults = default_parameter_settings();
  for (int i = 0; i < kNumParams; ++i)
    if (effect_of_param(i) == effect && !motor.parameters[static_cast<std::size_t>(i)].in_file)
      motor.parameters[static_cast<std::size_t>(i)] = defaults[static_cast<std::size_t>(i)];
  motor.text = format_motor_file(motor);
}

MotorFile motor_of(const CalibrationResult& calibration) {
  MotorFile motor = parse_motor_file(calibration.motor_text, calibration.motor_file + " (as kept in the calibration)");
  motor.path = calibration.motor_file;
  motor.effects = calibration.effects;
  for (int i = 0; i < kNumParams; ++i) {
    const int effect = effect_of_param(i);
    // The parameters of effects the model lacks were not part of the calibration: keep the file's.
    if (effect >= 0 && !(motor.effects & effect_bit(effect))) continue;
    const ParameterResult& r = calibration.parameters[static_cast<std::size_t>(i)];
    ParameterSetting& s = motor.parameters[static_cast<std::size_t>(i)];
    s.min = r.min;
    s.max = r.max;
    s.calibrate = r.calibrated;
  }
  return motor;
}

Split split_of(const CalibrationResult& calibration, const data::Dataset& dataset) {
  auto find = [&](const std::string& name) {
    for (std::size_t i = 0; i < dataset.cycles.size(); ++i)
      if (dataset.cycles[i].name == name) return i;
    throw std::invalid_argument("the calibration's cycle '" + name +
                                "' is not in the data (give the data it was made from, or --test-cycles)");
  };
  Split split;
  for (const std::string& name : calibration.train_cycles) split.train.push_back(find(name));
  for (const std::string& name : calibration.test_cycles) split.test.push_back(find(name));
  split.rule = calibration.split_rule;
  return split;
}

}  // namespace lptn::diagnose
