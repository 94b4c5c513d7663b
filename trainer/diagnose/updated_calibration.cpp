// A calibration carried forward to the model diagnose settled on.
#include "trainer/calibrate/calibration_result.hpp"
#include "trainer/lm/lm_result.hpp"
#include "trainer/diagnose/diagnose.hpp"

namespace lptn::diagnose {

CalibrationResult updated_calibration(const CalibrationResult& calibration, const MotorFile& motor, const lm::LmReport& fit,
                                      DatasetRef dataset, const Split& split, const std::string& note) {
  CalibrationResult r = calibration;
  r.motor = motor;
  r.motor.path = calibration.motor.path;
  r.effects = motor.effects;
  // The parameters of an effect added since take the motor's settings; the others keep theirs.
  for (int i = 0; i < kNumParams; ++i) {
    const int effect = effect_of_param(i);
    if (effect >= 0 && (motor.effects & effect_bit(effect)) && !(calibration.effects & effect_bit(effect)))
      r.parameters[static_cast<std::size_t>(i)] = parameter_result(motor, i);
  }
  std::vector<std::string> fitted;
  for (std::size_t c : split.train) fitted.push_back(dataset.cycles[c].name);
  lm::record_lm_fit(r, fit, FreeParameters::from_motor(motor), fitted, {{"refit", note}});
  r.details["note"] = note;
  score_calibration(r, motor, dataset, split);
  return r;
}

}  // namespace lptn::diagnose
