#include "trainer/calibrate/calibration_result.hpp"

#include <map>
#include <stdexcept>

#include "hostio/bad_input.hpp"
#include "hostio/sha256.hpp"
#include "hostio/worker_threads.hpp"
#include "hostio/utc_stamp.hpp"
#include "lptn/version.hpp"

namespace lptn::calibrate {

ParameterResult parameter_result(const MotorFile& motor, int i) {
  const ParameterSetting& s = motor.parameters[static_cast<std::size_t>(i)];
  ParameterResult p;
  p.name = param_spec(i).name;
  p.unit = param_spec(i).unit;
  p.value = p.initial = s.initial;
  p.min = s.min;
  p.max = s.max;
  const int effect = effect_of_param(i);
  p.calibrated = s.calibrate && (effect < 0 || (motor.effects & effect_bit(effect)));
  return p;
}

CalibrationResult new_calibration(const MotorFile& motor, const std::string& motor_path, DatasetRef dataset,
                                  const Split& split) {
  CalibrationResult r;
  r.created_utc = hostio::utc_now();
  r.lptn_version = kNameAndVersion;
  r.motor = motor;
  r.motor.path = motor_path;
  r.effects = motor.effects;
  for (int i = 0; i < kNumParams; ++i) r.parameters.push_back(parameter_result(motor, i));
  // The files behind the cycles, hashed (each once, over the cores), and one hash over them all
  // (in cycle order).
  std::map<std::string, std::string> hashes;
  std::vector<std::filesystem::path> to_hash;
  for (std::size_t i = 0; i < dataset.cycles.size(); ++i) {
    const std::string file = dataset.cycles[i].file.string();
    if (hashes.count(file)) continue;
    hashes[file] = dataset.file_sha256(i);  // a shared load hashed every file on its process
    if (hashes[file].empty()) to_hash.push_back(dataset.cycles[i].file);
  }
  const std::vector<std::string> taken = hostio::sha256_files(to_hash, hostio::worker_threads());
  for (std::size_t i = 0; i < to_hash.size(); ++i) hashes[to_hash[i].string()] = taken[i];
  std::string all;
  for (const data::Cycle& c : dataset.cycles) {
    const std::string& hash = hashes.at(c.file.string());
    DataFile f;
    f.cycle = c.name;
    f.file = c.file.filename().string();
    f.sha256 = hash;
    f.map_file = c.map_file.string();
    f.map_sha256 = c.map_sha256;
    r.data.push_back(std::move(f));
    all += hash;
  }
  r.data_sha256 = hostio::sha256_hex(all.data(), all.size());
  for (std::size_t c : split.train) r.train_cycles.push_back(dataset.cycles[c].name);
  for (std::size_t c : split.test) r.test_cycles.push_back(dataset.cycles[c].name);
  r.split_rule = split.rule;
  return r;
}

void score_calibration(CalibrationResult& result, const MotorFile& motor, DatasetRef dataset,
                       const Split& split) {
  const Model<double> model = motor.model();
  result.train = evaluate_split(model, result.values(), dataset, split.train);
  result.test = evaluate_split(model, result.values(), dataset, split.test);
}

MotorFile motor_of(const CalibrationResult& calibration) {
  MotorFile motor = calibration.motor;
  motor.effects = calibration.effects;
  for (int i = 0; i < kNumParams; ++i) {
    const int effect = effect_of_param(i);
    // The parameters of effects the model lacks were not part of the calibration: keep the file's.
    if (effect >= 0 && !(motor.effects & effect_bit(effect))) continue;
    const ParameterResult& r = calibration.parameters[static_cast<std::size_t>(i)];
    ParameterSetting& s = motor.parameters[static_cast<std::size_t>(i)];
    s.min = r.min;
    s.max = r.max;
    s.calibrate = r.calibrated;
  }
  return motor;
}

Split split_of(const CalibrationResult& calibration, const data::Dataset& dataset) {
  auto find = [&](const std::string& name) {
    for (std::size_t i = 0; i < dataset.cycles.size(); ++i)
      if (dataset.cycles[i].name == name) return i;
    throw hostio::BadInput("the calibration's cycle '" + name +
                                "' is not in the data (give the data it was made from, or --test-cycles)");
  };
  Split split;
  for (const std::string& name : calibration.train_cycles) split.train.push_back(find(name));
  for (const std::string& name : calibration.test_cycles) split.test.push_back(find(name));
  split.rule = calibration.split_rule;
  return split;
}

}  // namespace lptn::calibrate
