// The effect library: every effect the model can switch on by name. Registering a new effect is
// one line here (and its header); see effect.hpp for what an effect is. The dictionary's generic
// terms (dictionary.hpp) follow the named effects as one group.
#pragma once

#include "lptn/effects/air_heating.hpp"
#include "lptn/effects/airgap.hpp"
#include "lptn/effects/dictionary.hpp"
#include "lptn/effects/effect_list.hpp"
#include "lptn/effects/rotor_speed_convection.hpp"
#include "lptn/effects/sensor_lag.hpp"
#include "lptn/effects/windage.hpp"

namespace lptn {

using EffectLibrary = EffectList<effects::Airgap, effects::Windage, effects::AirHeating,
                                 effects::RotorSpeedConvection, effects::SensorLag, terms::Dictionary>;

}  // namespace lptn
