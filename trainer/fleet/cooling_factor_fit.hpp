// One motor's cooling factor (cooling_factor.hpp) against the motor type's parameters: the fleet
// calibration's per-motor fit.
#pragma once

#include <cstddef>
#include <vector>

#include "lptn/model.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/model/simulate.hpp"

namespace lptn::fleet {

struct CoolingFactorFit {
  double factor = 1;
  double log_std_error = 0;  // of ln(factor): the factor is factor * exp(+-log_std_error)
  std::vector<model::InitialOffsets<double>> offsets;  // per listed cycle
  std::size_t residuals = 0;
  double rmse_k = 0;             // stator and rotor pooled, at the fitted factor
  double correlation_time = 1;   // the standard error accounts for it, as fit_lm's do
  int iterations = 0;
};

// Fits ln(factor) on the listed cycles (with each cycle's two initial offsets) by
// Levenberg-Marquardt, every other parameter held at `params`. The residuals are fit_lm's (model
// minus the stator sensor and, where measured, the rotor, on the grid); exact derivatives from
// Jets through the simulation. The standard error is the Gauss-Newton one with the offsets
// profiled out, inflated by the residuals' correlation time. Throws std::runtime_error when no
// cycle has a measurement.
CoolingFactorFit fit_cooling_factor(const Model<double>& model, const ParamVector<double>& params,
                                    const data::Dataset& dataset, const std::vector<std::size_t>& cycles,
                                    int threads);

}  // namespace lptn::fleet
