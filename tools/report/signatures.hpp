// What each effect of the library would add to the model, as one number per grid step: the
// "signature" that lptn report plots the residual against when lptn diagnose names the effect. A
// missing effect leaves a residual that follows its signature (common/lptn/effects/*.hpp).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "lptn/model.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/model/simulate.hpp"

namespace lptn::report {

struct Signature {
  std::string label;  // what it is, for the axis
  std::string unit;
  std::vector<float> values;  // per grid step; NaN where an input is missing
};

// The signature of a library effect over one simulated cycle; nullopt for a name the report
// does not know (a newer diagnose may name effects this build has no signature for).
std::optional<Signature> effect_signature(std::string_view effect, const Model<double>& model,
                                          const ParamVector<double>& params, const data::Cycle& cycle,
                                          const model::CycleSimulation& sim);

// Any effect or term at the values diagnose's refit found (a name of EffectLibrary; values by
// parameter index, the paper's as the refit readjusted them where given): how much the refit
// changes the sensor reading on the effect's node's side (stator for a library effect) against the
// calibration. The residual (model - measured) of a model that lacks it follows this with slope
// -1 where the refit explains it, whatever the term's form; nullopt for an unknown name.
struct RefitValue {
  int param;
  double value;
};
std::optional<Signature> refit_signature(std::string_view effect, const std::vector<RefitValue>& values,
                                         const Model<double>& model, const ParamVector<double>& params,
                                         const data::Cycle& cycle, const model::CycleSimulation& sim);

}  // namespace lptn::report
