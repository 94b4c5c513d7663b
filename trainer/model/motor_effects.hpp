// Effects of the library switched on in a motor by name: what `lptn calibrate --effect` and
// `lptn diagnose` do to the motor file they were given.
#pragma once

#include <string_view>

#include "trainer/model/motor_file.hpp"

namespace lptn::model {

// The library's effect called `name`; throws BadInput ("OPTION: unknown effect 'x'
// (known: ...)").
int effect_by_name(std::string_view name, std::string_view option);

// Switches `effect` on with the library's parameter settings (calibrated from its initial value)
// and rewrites motor.text, so that a calibration made with it keeps a text that rebuilds this model.
void enable_effect(MotorFile& motor, int effect);

}  // namespace lptn::model
