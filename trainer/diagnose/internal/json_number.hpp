// A number for the diagnosis file: NaN or infinity (no test cycles, no standard error, too few
// readings) as null, which JSON can hold and a reader takes as "not known".
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>

namespace lptn::diagnose::internal {

inline nlohmann::json json_number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace lptn::diagnose::internal
