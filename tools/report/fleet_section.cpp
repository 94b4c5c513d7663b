#include "tools/report/fleet_section.hpp"

#include <cmath>

#include "trainer/fleet/fleet_file.hpp"

namespace lptn::report {
namespace {

nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace

nlohmann::json fleet_section(const std::filesystem::path& fleet_file) {
  const fleet::FleetFile f = fleet::load_fleet_file(fleet_file);
  nlohmann::json j = {{"file", fleet_file.string()},
                      {"motor", f.pooled.motor.name},
                      {"created_utc", f.pooled.created_utc},
                      {"rounds", f.rounds},
                      {"family_alpha", f.family_alpha},
                      {"threshold_t", number_or_null(f.threshold_t)},
                      {"motors", nlohmann::json::array()},
                      {"outliers", nlohmann::json::array()}};
  for (const fleet::FleetFileMotor& m : f.motors) {
    j["motors"].push_back({{"id", m.id},
                           {"cooling_factor", m.cooling_factor},
                           {"cooling_factor_std", m.cooling_factor_std},
                           {"t", number_or_null(m.t)},
                           {"outlier", m.outlier},
                           {"reason", m.reason},
                           {"cycles", m.cycles},
                           {"rmse_stator_k", m.rmse_stator_k},
                           {"rmse_rotor_k", number_or_null(m.rmse_rotor_k)}});
    if (m.outlier) j["outliers"].push_back(m.id);
  }
  return j;
}

}  // namespace lptn::report
