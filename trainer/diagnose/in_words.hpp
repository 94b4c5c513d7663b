// An effect or dictionary term in physical words, with its fitted size: what diagnose prints for a
// candidate, e.g. "extra heat in the stator winding growing as I^2 f^k with k = 1.62, 1.21 kW at
// the rated point".
#pragma once

#include <string>

#include "lptn/model.hpp"

namespace lptn::diagnose {

std::string in_words(int effect, const ParamVector<double>& values);

// "stator_winding" etc. for a term's node; empty for a library effect.
std::string node_id(int effect);

}  // namespace lptn::diagnose
