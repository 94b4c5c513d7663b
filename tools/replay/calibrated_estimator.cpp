#include "tools/replay/calibrated_estimator.hpp"

#include "lptn/firmware/parameter_uncertainty.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::replay {

std::unique_ptr<CalibratedEstimatorConfig> estimator_config_from(const calibrate::CalibrationResult& c, const std::string& shown_as,
                                                                  const fw::BusDecoder& bus) {
  auto out = std::make_unique<CalibratedEstimatorConfig>();
  out->config = fw::default_config<double>(c.motor.constants, c.effects, c.values(), bus);
  double ln_std[kNumParams];
  for (int j = 0; j < kNumParams; ++j) {
    ln_std[j] = 0.0;
    if (static_cast<std::size_t>(j) >= c.parameters.size()) continue;
    const calibrate::ParameterResult& p = c.parameters[static_cast<std::size_t>(j)];
    ln_std[j] = fw::parameter_ln_std(p.value, p.std_error, p.calibrated, p.identifiable);
  }
  fw::apply_calibration_uncertainty(out->config, ln_std, c.test.stator.samples > 0, c.test.stator.rmse_k);
  if (!c.has_actor) return out;

  const calibrate::ActorExport& a = c.actor;
  if (a.layers.size() != 3 || a.layers[0].in != 2 || a.layers[0].out > 256 || a.layers[2].out > 32 ||
      a.layers[2].out != static_cast<int>(a.param_indices.size()))
    throw calibrate::CalibrationFileError(shown_as + ": field 'actor': not the firmware's shape (2 -> at most 256 -> 256 -> at most 32)");
  for (int l = 0; l < 3; ++l) {
    out->weights[l] = a.layers[l].weight;
    out->biases[l] = a.layers[l].bias;
  }
  out->actor_view = ActorView{2,
                              a.layers[0].out,
                              a.layers[2].out,
                              out->weights[0].data(),
                              out->biases[0].data(),
                              out->weights[1].data(),
                              out->biases[1].data(),
                              out->weights[2].data(),
                              out->biases[2].data()};
  for (int j : a.param_indices) {
    out->param_index.push_back(j);
    out->param_min.push_back(c.parameters[j].min);
    out->param_max.push_back(c.parameters[j].max);
  }
  fw::ActorSchedule& s = out->config.actor;
  s.actor = &out->actor_view;
  for (int k = 0; k < 2; ++k) {
    s.obs_offset[k] = a.obs_offset[k];
    s.obs_scale[k] = a.obs_scale[k];
  }
  s.param_index = out->param_index.data();
  s.param_min = out->param_min.data();
  s.param_max = out->param_max.data();
  return out;
}

}  // namespace lptn::replay
