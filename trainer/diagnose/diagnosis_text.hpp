// A diagnosis in words, as `lptn diagnose` prints it: the baseline, each sensor against its noise,
// the sensor-fault and drift checks, the candidates' table, why each is or is not recommended, and
// the one recommendation (or why there is none, and what to do instead). Beside the diagnosis, so
// that every program that diagnoses says the same.
#pragma once

#include <string>

#include "trainer/diagnose/diagnose.hpp"

namespace lptn::diagnose {

// The printed diagnosis, lines ending in '\n'; `level` is the likelihood-ratio test's (Settings::level).
std::string diagnosis_text(const Diagnosis& diagnosis, double level);

// "windage, sensor_lag", or "none": the effects a motor has switched on.
std::string effect_list(EffectSet effects);

// "1.234", or "-" where there is no figure (no test cycles).
std::string kelvin(double v);

}  // namespace lptn::diagnose
