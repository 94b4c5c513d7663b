// A calibration carried forward to the model diagnose settled on.
#include "trainer/calibrate/calibration_result.hpp"
#include "trainer/lm/lm_result.hpp"
#include "trainer/diagnose/diagnose.hpp"

namespace lptn::diagnose {

calibrate::CalibrationResult updated_calibration(const calibrate::CalibrationResult& calibration,
                                                 const model::MotorFile& motor, const lm::LmReport& fit,
                                                 calibrate::DatasetRef dataset, const calibrate::Split& split,
                                                 const std::string& note) {
  calibrate::CalibrationResult r = calibration;
  // The refit is the new calibration's fit, made on the data diagnose read: its record names those
  // files as they were read (each one's hash and data map), the split and the lptn that made it,
  // not the record of the calibration it started from. Copied, a diagnosis of other data (which it
  // warns of) wrote a calibration that `lptn check` and `lptn report` then took for one of the
  // first data's, and whose training cycles were not the ones fitted.
  const calibrate::CalibrationResult made_now = calibrate::new_calibration(motor, calibration.motor.path.string(), dataset, split);
  r.created_utc = made_now.created_utc;
  r.lptn_version = made_now.lptn_version;
  r.data = made_now.data;
  r.data_sha256 = made_now.data_sha256;
  r.train_cycles = made_now.train_cycles;
  r.test_cycles = made_now.test_cycles;
  r.split_rule = made_now.split_rule;
  r.motor = motor;
  r.motor.path = calibration.motor.path;
  r.effects = motor.effects;
  // The parameters of an effect added since take the motor's settings; the others keep theirs.
  for (int i = 0; i < kNumParams; ++i) {
    const int effect = effect_of_param(i);
    if (effect >= 0 && (motor.effects & effect_bit(effect)) && !(calibration.effects & effect_bit(effect)))
      r.parameters[static_cast<std::size_t>(i)] = calibrate::parameter_result(motor, i);
  }
  std::vector<std::string> fitted;
  for (std::size_t c : split.train) fitted.push_back(dataset.cycles[c].name);
  lm::record_lm_fit(r, fit, calibrate::FreeParameters::from_motor(motor), fitted, {{"refit", note}});
  r.details["note"] = note;
  calibrate::score_calibration(r, motor, dataset, split);
  return r;
}

}  // namespace lptn::diagnose
