#include "trainer/workflow/diagnose.hpp"

#include "hostio/bad_input.hpp"
#include "hostio/process_group.hpp"
#include "hostio/utc_stamp.hpp"
#include "trainer/calibrate/calibration_outcome.hpp"
#include "trainer/calibrate/calibration_result.hpp"
#include "trainer/calibrate/shared_dataset.hpp"
#include "trainer/check/sensor_corrections.hpp"
#include "trainer/diagnose/diagnosis_text.hpp"
#include "trainer/model/motor_plausibility.hpp"

namespace lptn::workflow {
namespace {

// "before" as the calibration file has it, whatever the data given: its own figures on its own data.
std::string file_figures(const calibrate::CalibrationResult& c) {
  auto side = [](const char* name, const calibrate::SplitMetrics& m) {
    std::string out = std::string(name) + " stator " + (m.stator.samples ? diagnose::kelvin(m.stator.rmse_k) : "-") + " K";
    if (m.rotor.samples) out += ", rotor " + diagnose::kelvin(m.rotor.rmse_k) + " K";
    return out;
  };
  return side("train", c.train) + "; " + side("test", c.test);
}

nlohmann::json file_figures_json(const calibrate::CalibrationResult& c) {
  auto number = [](const ErrorMetrics& m) { return m.samples ? nlohmann::json(m.rmse_k) : nlohmann::json(nullptr); };
  return {{"train", {{"rmse_stator_k", number(c.train.stator)}, {"rmse_rotor_k", number(c.train.rotor)}}},
          {"test", {{"rmse_stator_k", number(c.test.stator)}, {"rmse_rotor_k", number(c.test.rotor)}}}};
}

// The data's relation to the calibration and what diagnose did with it, for --json: the figures
// the calibration file has, whether this is its data, and that the baseline is a refit.
nlohmann::json provenance_json(const calibrate::CalibrationResult& c, const check::Provenance& p, const diagnose::Diagnosis& d) {
  return {{"calibration_figures", file_figures_json(c)},
          {"calibration_data", p.all_seen()},
          {"never_seen", p.unseen_names()},
          {"constants", p.constants},
          {"summary", p.summary()},
          {"refit", true},
          {"refit_iterations", d.baseline.iterations}};
}

std::string not_its_data(const DiagnosisRequest& q, const check::Provenance& p) {
  if (p.all_seen()) return {};
  std::string data;
  for (const std::string& d : q.data) data += (data.empty() ? "" : " ") + d;
  return "this is not the calibration's data: " + p.summary() +
         " never seen by it. The training and test cycles below are diagnose's own split of this data (" +
         (q.test_cycles.empty() ? "by the calibration's cycle names" : "--test-cycles") +
         "), and every figure below is a refit's on it, not the calibration's. Whether the calibration holds on "
         "this data: lptn check --data " + data + " --calibration " + q.calibration +
         (p.other_map() ? ". Where these are the calibration's files, read them through the data map it read them "
                          "through (--map)"
                        : "");
}

}  // namespace

DiagnosisOutcome diagnose(const DiagnosisRequest& q, const DiagnosisEvents& events) {
  if (!(q.level > 0 && q.level < 0.5)) throw hostio::BadInput("--level: must be in (0, 0.5), got " + std::to_string(q.level));
  // Under mpirun the LM refits are shared over the processes (each simulates its share of the
  // cycles); every rank holds the whole dump and does the rest too.
  const hostio::ProcessGroup& group = hostio::ProcessGroup::world();
  const calibrate::CalibrationResult calibration = calibrate::load_calibration(q.calibration);
  const MotorFile motor = calibrate::motor_of(calibration);
  std::vector<std::filesystem::path> paths(q.data.begin(), q.data.end());
  data::Dataset loaded = data::load_fleet_dump(paths, data::with_data_map(q.map));
  DiagnosisPlan plan;
  plan.corrections = check::correct_as_calibrated(loaded, calibration);
  if (events.input_warnings) {
    std::vector<std::string> warnings = input_warnings(loaded, motor);
    if (const std::string caution = calibrate::status_caution(calibration, q.calibration, false); !caution.empty())
      warnings.insert(warnings.begin(), caution);
    events.input_warnings(warnings);
  }
  const calibrate::SharedDataset shared = calibrate::share_work(std::move(loaded), group);
  const data::Dataset& dataset = shared.data;
  // By name and file hash: a dump that only shares the calibration's cycle names is not its data.
  plan.provenance = check::provenance(calibration, dataset, check::motor_beside(q.data));
  const calibrate::Split split = q.test_cycles.empty() ? calibrate::split_of(calibration, dataset) : calibrate::split_cycles(dataset, q.test_cycles, 0.0, 0);
  plan.motor_name = motor.name;
  plan.effects = motor.effects;
  plan.train_cycles = split.train.size();
  plan.test_cycles = split.test.size();
  plan.calibration_figures = file_figures(calibration);
  plan.not_its_data = not_its_data(q, plan.provenance);
  if (events.started) events.started(plan);
  diagnose::Settings settings;
  settings.level = q.level;

  DiagnosisOutcome out;
  if (!q.automatic) {
    out.rounds.push_back(diagnose::diagnose(motor, calibration.values(), shared, split, settings, events.progress));
    out.json = diagnose::to_json(out.last());
    out.json["data"] = provenance_json(calibration, plan.provenance, out.last());
    return out;
  }
  diagnose::Selection s =
      diagnose::select_effects(motor, calibration.values(), shared, split, settings, events.progress, events.round_done);
  out.rounds = std::move(s.rounds);
  out.added = s.added;
  out.json = diagnose::to_json(out.last());  // the final model's figures
  out.json["data"] = provenance_json(calibration, plan.provenance, out.rounds.front());
  out.json["added"] = out.added;
  out.json["rounds"] = nlohmann::json::array();
  for (const diagnose::Diagnosis& d : out.rounds) out.json["rounds"].push_back(diagnose::to_json(d));
  if (!q.updated_calibration) return out;
  calibrate::CalibrationResult r = diagnose::updated_calibration(calibration, s.motor, out.last().baseline, shared, split,
                                                      "lptn diagnose --auto from " + q.calibration);
  r.created_utc = hostio::utc_now();
  out.updated = std::move(r);
  return out;
}

}  // namespace lptn::workflow
