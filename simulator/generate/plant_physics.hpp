// Physics the synthetic plant can have that the model cannot: neither a library effect nor any
// single dictionary term reproduces it exactly. Every real motor has some; these test that
// `lptn diagnose` tells the truth about it (docs/diagnosis.md).
//
//   eddy_loss        an extra loss in the stator winding with its own operating-point dependence:
//                    1.2 kW (I/I_r)^2 ((f/f_r)^1.5 + 0.3 (f/f_r)^3) / 1.3 (eddy currents in the
//                    conductors, growing faster than any one power of frequency at high frequency)
//   cooling_fouling  the later half of the cycles cool 30 % worse than the airflow signal says
//                    (a clogging filter): every conductance to air times 0.7 from cycle
//                    floor(N/2) + 1 on
//   frame_mass       a fifth thermal mass: the stator core loses its heat to the air through the
//                    frame (600 kJ/K; 300 W/K core to frame, 150 W/K frame to air at nominal
//                    airflow) instead of directly
//   windage_cubed    friction and windage growing with speed cubed, 900 W at base speed, 60 % into
//                    the rotor core and 40 % into the stator winding (the library's windage is
//                    speed squared, into the rotor core only)
//   step_loss        a loss that switches on: 700 W into the stator winding while the stator
//                    frequency is above 50 Hz (the converter changes its modulation there, and the
//                    current's harmonics heat the winding), nothing below
//   recirculation    warm exhaust air drawn back in at low airflow: the air the motor breathes is
//                    ambient plus a share s = 0.8 (1 - V/V_n) of the exhaust's rise below nominal
//                    airflow, none above; the logger's ambient stays the outside air's (both sides
//                    breathe the warmer air)
//
// The extra heat and the frame are added to the truth at every (quarter-step) integration step,
// explicitly: their time constants are minutes, the step 25 ms.
#pragma once

#include <cstdint>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

#include "lptn/model.hpp"

namespace lptn::gen {

enum class PlantPhysics : std::uint32_t {
  eddy_loss,
  cooling_fouling,
  frame_mass,
  windage_cubed,
  step_loss,
  recirculation,
  count
};
using PlantPhysicsSet = std::uint32_t;

inline constexpr std::string_view kPlantPhysicsNames[] = {"eddy_loss",     "cooling_fouling", "frame_mass",
                                                          "windage_cubed", "step_loss",       "recirculation"};
static_assert(std::size(kPlantPhysicsNames) == static_cast<std::size_t>(PlantPhysics::count));
constexpr PlantPhysicsSet plant_bit(PlantPhysics p) { return PlantPhysicsSet{1} << static_cast<std::uint32_t>(p); }

// The physics of that name, or count.
PlantPhysics plant_physics_index(std::string_view name);
std::vector<std::string> plant_physics_names(PlantPhysicsSet set);

// The factor on every conductance to air in cycle `index` (0-based) of `cycles`.
double cooling_factor(PlantPhysicsSet set, int index, int cycles);

// The plant's own states beyond the model's (the frame's temperature).
struct PlantExtraState {
  double frame_c = 0;
};

// The true parameters of a cycle: the plant's, with what `set` changes in them.
ParamVector<double> cycle_parameters(PlantPhysicsSet set, const ParamVector<double>& truth, int index, int cycles);

// At the start of a cycle, soaked through at `soak_c`.
PlantExtraState initial_extra_state(double soak_c);

// The inputs the plant's truth steps with: `in` with the air the motor breathes (warmer than the
// logged ambient where exhaust air recirculates), for the nodes `x` and the cycle's true `params`.
Inputs<double> plant_inputs(PlantPhysicsSet set, const MotorConstants<double>& m, const Inputs<double>& in,
                            const double* x, const ParamVector<double>& params);

// One explicit step of dt seconds of what the model cannot do, after the model's own step.
void step_plant_physics(PlantPhysicsSet set, const MotorConstants<double>& m, const Inputs<double>& in, double* x,
                        PlantExtraState& extra, double dt);

}  // namespace lptn::gen
