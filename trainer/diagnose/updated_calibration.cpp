// A calibration carried forward to the model diagnose settled on.
#include "trainer/diagnose/diagnose.hpp"

namespace lptn::diagnose {

CalibrationResult updated_calibration(const CalibrationResult& calibration, const MotorFile& motor, const LmReport& fit,
                                      const data::Dataset& dataset, const Split& split, const std::string& note) {
  CalibrationResult r = calibration;
  r.motor_text = motor.text;
  r.effects = motor.effects;
  for (int i = 0; i < kNumParams; ++i) {
    const ParameterSetting& s = motor.parameters[static_cast<std::size_t>(i)];
    ParameterResult& p = r.parameters[static_cast<std::size_t>(i)];
    const int effect = effect_of_param(i);
    const bool added = effect >= 0 && (motor.effects & effect_bit(effect)) && !(calibration.effects & effect_bit(effect));
    if (added) {
      p.initial = s.initial;
      p.min = s.min;
      p.max = s.max;
      p.calibrated = s.calibrate;
    }
    p.value = fit.values[i];
    p.std_error = fit.std_error[i];
  }
  r.correlated = fit.correlated;
  r.method = "lm";
  r.has_actor = false;  // a TD3 actor belongs to the model it was trained for
  r.settings = {{"refit", note}};
  r.details = {{"iterations", fit.iterations},   {"converged", fit.converged}, {"termination", fit.termination},
               {"initial_cost_k2", fit.initial_cost}, {"final_cost_k2", fit.final_cost},
               {"residuals", fit.residuals},     {"rmse_k", fit.rmse_k},     {"correlation_time", fit.correlation_time},
               {"note", note}};
  r.seconds = fit.seconds;
  const Model<double> model = motor.model();
  r.train = evaluate_split(model, fit.values, dataset, split.train);
  r.test = evaluate_split(model, fit.values, dataset, split.test);
  return r;
}

}  // namespace lptn::diagnose
