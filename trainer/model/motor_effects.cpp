#include "trainer/model/motor_effects.hpp"

#include <array>
#include <stdexcept>
#include <string>

#include "hostio/bad_input.hpp"

namespace lptn::model {

int effect_by_name(std::string_view name, std::string_view option) {
  const int e = effect_index(name);
  if (e >= 0) return e;
  std::string known;
  for (std::string_view n : EffectLibrary::kNames) known += (known.empty() ? "" : ", ") + std::string(n);
  throw hostio::BadInput(std::string(option) + ": unknown effect '" + std::string(name) + "' (known: " + known + ")");
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

}  // namespace lptn::model
