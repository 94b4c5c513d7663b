// The report's Fleet section: each motor's cooling factor with its error bar, the outliers named,
// from a fleet.json (lptn calibrate --fleet).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

namespace lptn::report {

// {"file", "motor", "created_utc", "rounds", "family_alpha", "threshold_t", "motors": [{"id",
// "cooling_factor", "cooling_factor_std", "t", "outlier", "reason", "cycles", "rmse_stator_k",
// "rmse_rotor_k"}], "outliers": [ids]}. Throws CalibrationFileError for a bad file.
nlohmann::json fleet_section(const std::filesystem::path& fleet_file);

}  // namespace lptn::report
