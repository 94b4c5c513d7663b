// A motor file checked against its own nameplate: each value the physics of an induction motor of
// that rated power, voltage and current makes implausible, with the range that would be plausible.
// These are warnings: the loader (motor_file.hpp) already refuses what makes the model impossible
// (a negative capacitance, swapped bounds, a share above one, a magnetizing current above rated).
//
// The ranges, from the physics (P rated power, V rated line voltage, I rated phase current):
//   rated power            0.4..1.0 x sqrt(3) V I: the output is the apparent input times
//                          efficiency and power factor
//   stator, rotor R at 20 C  3 R I^2 at rated current (the rotor's I^2 - Im^2) is 0.1..15 % of P:
//                          large traction motors lose 1..3 % in each winding, small ones up to ~10 %
//   stator alpha           0.003..0.0045 /K (copper 0.00393, aluminium 0.00403)
//   rotor alpha            0.001..0.0045 /K (cages of copper, aluminium, or brass/bronze bars ~0.0015)
//   magnetizing current    10..70 % of I (20..50 % usual; a large air gap more)
//   stray loss at rated    0..5 % of P (IEC 60034-2-1 assumes 0.5..2.5 %)
//   iron loss at rated     0..10 % of P (1..3 % usual)
//   iron_alpha             1..2 (Steinmetz: hysteresis ~ f, eddy currents ~ f^2)
//   iron_beta              1.5..3 (Steinmetz flux exponent; eddy currents B^2)
//   harmonic loss          each point 0..10 % of P
//   loss factors k_stemp, k_rtemp   0.5..2 (a correction of the copper loss, not another loss)
//   each capacitance       0.005..10 J/K per W of P: motors weigh 0.5..10 kg per kW, the metals
//                          hold 0.39..0.9 kJ/(kg K), a node is a few % to most of the mass
//                          (the example motor: 0.07..0.77 J/K per W)
//   nominal airflow        1.7e-7..6.3e-5 m^3/s per W of P: losses of 1..15 % of P carried off
//                          with the air warming 2..50 K (rho c_p = 1200 J/(m^3 K))
//   airflow_exponent       0.3..1 (forced convection: Nu ~ Re^0.5 laminar .. Re^0.8 turbulent)
//   min_airflow_fraction   0..0.5 (natural convection keeps a tenth or so of the forced cooling)
//   conductances (W/K)     to the air 0.001..15 W/K per kW of P; within stator or rotor (and the
//                          air gap) 0.001..50 W/K per kW: the total losses (1..15 % of P) at rises
//                          of 10..200 K; an initial value outside, or bounds wholly outside, is flagged
//   windage at base speed  0..5 % of P
#pragma once

#include <string>
#include <vector>

#include "trainer/data/dataset.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::model {

struct MotorFinding {
  std::string key;        // the motor file's key path: "electrical.stator_resistance_20c_ohm",
                          // "parameters.lambda_1s.initial"
  double value = 0;
  // "stator_resistance_20c_ohm = 80 gives 3.2 MW of copper loss at rated current (rated power 310 kW)"
  std::string message;
  std::string plausible;  // "0.0078..1.2 ohm"
  int line = 0;           // the key's line in the motor file (0: not known, e.g. no text kept)
  // How far outside its range, in decades of value/nearest end (for a linear range, of distance
  // over the range's width): the findings come most implausible first.
  double how_far = 0;
};

// Every implausible value of the motor file, most implausible first; empty for a plausible motor.
std::vector<MotorFinding> check_motor_plausibility(const MotorFile& motor);

// One line: "FILE:LINE: key 'KEY': MESSAGE; plausible RANGE" (":LINE" left out when not known).
std::string format_motor_finding(const MotorFile& motor, const MotorFinding& finding);

// check_motor_plausibility's findings, formatted: one line each, for a command to print as warnings.
std::vector<std::string> motor_warnings(const MotorFile& motor);

// Why the motor file's values might make the model not simulable, in one line: the most implausible
// value ("motor.toml:14: key 'electrical.stator_resistance_20c_ohm': stator_resistance_20c_ohm = 80
// gives 3.2 MW of copper loss at rated current (rated power 310 kW); plausible 0.0078..1.2 ohm"),
// then "(and N more implausible: KEY, KEY)". Empty when every value is plausible. For a command to
// say when the model's losses or temperatures come out non-finite (lptn calibrate, simulate).
std::string implausible_values_summary(const MotorFile& motor);

// What a command that runs the model on a dump repeats before its results, one line each:
// data::inspection_warnings(dataset, the motor's nameplate) (what lptn inspect --motor finds in the
// data: ignored or misnamed columns, gaps, another pole count) and then motor_warnings(motor).
std::vector<std::string> input_warnings(const data::Dataset& dataset, const MotorFile& motor);

}  // namespace lptn::model
