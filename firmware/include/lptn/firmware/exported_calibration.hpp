// The estimator's configuration from a header that `lptn export` wrote: include that header
// (namespace lptn::calibration) first, then this. The firmware's way to get its calibration: the
// values are compile-time constants, nothing is parsed on the target.
#pragma once

#include "lptn/firmware/estimator_config.hpp"
#include "lptn/firmware/parameter_uncertainty.hpp"


namespace lptn::fw {

template <class T>
EstimatorConfig<T> config_from_exported_header() {
  namespace cal = lptn::calibration;
  ParamVector<T> params{};
  for (int i = 0; i < kNumParams; ++i) params[i] = T(cal::kParams[i]);
  EstimatorConfig<T> c = default_config<T>(cal::motor_constants().template cast<T>(), cal::kEffects, params);
  double ln_std[kNumParams];
  for (int i = 0; i < kNumParams; ++i)
    ln_std[i] = parameter_ln_std(cal::kParams[i], cal::kParamStdError[i], cal::kParamCalibrated[i], cal::kParamIdentifiable[i]);
  apply_calibration_uncertainty(c, ln_std, cal::kHasTestMetrics, cal::kTestRmseStatorK);
#ifdef LPTN_CALIBRATION_HAS_ACTOR
  c.actor.actor = &cal::kActor;
  for (int k = 0; k < 2; ++k) {
    c.actor.obs_offset[k] = cal::kActorObsOffset[k];
    c.actor.obs_scale[k] = cal::kActorObsScale[k];
  }
  c.actor.param_index = cal::kActorParamIndex;
  c.actor.param_min = cal::kActorParamMin;
  c.actor.param_max = cal::kActorParamMax;
#endif
  return c;
}

}  // namespace lptn::fw
