// The synthetic plant's true motor: the example motor of the contract, the conductances it really
// has (unknown to the user, who starts from the motor file's initial guesses) and the true size
// of every effect the paper's model lacks, for when one is hidden in the data.
#pragma once

#include "lptn/model.hpp"
#include "simulator/plant/motor_spec.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::gen {

// The motor file a user of the generated data starts from (the contract's example motor, the
// paper's model, no effects).
model::MotorFile example_motor_file();

// The true parameter values the plant runs with.
ParamVector<double> true_parameters();

// The mechanical/electrical plant's view of the same motor.
plant::MotorSpec plant_motor_spec(const MotorConstants<double>& m);

}  // namespace lptn::gen
