#include "simulator/generate/plant_physics.hpp"

#include <algorithm>
#include <cmath>

namespace lptn::gen {
namespace {

constexpr double kFoulingFactor = 0.7;

constexpr double kEddyRatedW = 1200.0;
constexpr double kWindageBaseW = 900.0;
constexpr double kWindageRotorShare = 0.6;

constexpr double kFrameCapacitanceJPerK = 600e3;
constexpr double kCoreToFrameWPerK = 300.0;
constexpr double kFrameToAirWPerK = 150.0;
// With the frame, the stator core's direct path to the air is (almost) gone: the lower bound of
// the paper's lambda_2s.
constexpr double kDirectCoreToAirWPerK = 1.0;

constexpr double kStepLossW = 700.0;
constexpr double kStepLossAboveHz = 50.0;

constexpr double kRecirculationShare = 0.8;   // with the blower at a standstill
constexpr double kRecirculationBelow = 1.0;   // of nominal airflow

bool has(PlantPhysicsSet set, PlantPhysics p) { return (set & plant_bit(p)) != 0; }

}  // namespace

PlantPhysics plant_physics_index(std::string_view name) {
  for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(PlantPhysics::count); ++i)
    if (kPlantPhysicsNames[i] == name) return static_cast<PlantPhysics>(i);
  return PlantPhysics::count;
}

std::vector<std::string> plant_physics_names(PlantPhysicsSet set) {
  std::vector<std::string> out;
  for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(PlantPhysics::count); ++i)
    if (set & plant_bit(static_cast<PlantPhysics>(i))) out.emplace_back(kPlantPhysicsNames[i]);
  return out;
}

double cooling_factor(PlantPhysicsSet set, int index, int cycles) {
  return has(set, PlantPhysics::cooling_fouling) && index >= cycles / 2 ? kFoulingFactor : 1.0;
}

ParamVector<double> cycle_parameters(PlantPhysicsSet set, const ParamVector<double>& truth, int index, int cycles) {
  ParamVector<double> p = truth;
  const double k = cooling_factor(set, index, cycles);
  for (int i : kConductancesToAir) p[i] *= k;
  if (has(set, PlantPhysics::frame_mass)) p[kLambda2s] = kDirectCoreToAirWPerK;
  return p;
}

Inputs<double> plant_inputs(PlantPhysicsSet set, const MotorConstants<double>& m, const Inputs<double>& in,
                            const double* x, const ParamVector<double>& params) {
  Inputs<double> out = in;
  if (!has(set, PlantPhysics::recirculation)) return out;
  const double share = kRecirculationShare * std::max(0.0, 1.0 - in.airflow_m3s / (kRecirculationBelow * m.nominal_airflow_m3s));
  if (share <= 0) return out;
  // The inlet's rise d over ambient mixes in a share s of the exhaust's, which the heat to air Q
  // raises over the inlet by Q / (rho c_p V):  d = s (d + Q(d) / C),  Q(d) = Q0 - G d,  so
  // d = s Q0 / (C (1 - s) + s G), with G the conductances to air and Q0 their heat at ambient.
  const StepConductances<double> g = paper_conductances(m, in, params.data());
  double conductance = 0, heat_at_ambient = 0;
  for (int n = 0; n < kNumNodes; ++n) {
    conductance += g.to_air[n];
    heat_at_ambient += g.to_air[n] * (x[n] - in.ambient_c);
  }
  const double c = effects::AirHeating::kAirVolumetricHeatJPerM3K * effective_airflow(m, in.airflow_m3s);
  out.ambient_c += std::max(0.0, share * heat_at_ambient / (c * (1 - share) + share * conductance));
  return out;
}

PlantExtraState initial_extra_state(double soak_c) { return PlantExtraState{soak_c}; }

void step_plant_physics(PlantPhysicsSet set, const MotorConstants<double>& m, const Inputs<double>& in, double* x,
                        PlantExtraState& extra, double dt) {
  const double* c = m.capacitance_j_per_k;
  if (has(set, PlantPhysics::eddy_loss)) {
    const double i = std::abs(in.current_a) / m.rated_current_a, f = std::abs(in.frequency_hz) / m.rated_frequency_hz;
    const double p = kEddyRatedW * i * i * (std::pow(f, 1.5) + 0.3 * f * f * f) / 1.3;
    x[kStatorWinding] += p * dt / c[kStatorWinding];
  }
  if (has(set, PlantPhysics::step_loss) && std::abs(in.frequency_hz) > kStepLossAboveHz)
    x[kStatorWinding] += kStepLossW * dt / c[kStatorWinding];
  if (has(set, PlantPhysics::windage_cubed)) {
    const double n = std::abs(in.speed_rpm) / m.base_speed_rpm();
    const double p = kWindageBaseW * n * n * n;
    x[kRotorCore] += kWindageRotorShare * p * dt / c[kRotorCore];
    x[kStatorWinding] += (1 - kWindageRotorShare) * p * dt / c[kStatorWinding];
  }
  if (has(set, PlantPhysics::frame_mass)) {
    const double to_frame = kCoreToFrameWPerK * (x[kStatorCore] - extra.frame_c);
    const double to_air = kFrameToAirWPerK * airflow_factor(m, in.airflow_m3s) * (extra.frame_c - in.ambient_c);
    x[kStatorCore] -= to_frame * dt / c[kStatorCore];
    extra.frame_c += (to_frame - to_air) * dt / kFrameCapacitanceJPerK;
  }
}

}  // namespace lptn::gen
