#include "trainer/workflow/calibrate.hpp"

#include <string>
#include <string_view>
#include <vector>

#include "hostio/bad_input.hpp"
#include "trainer/calibrate/calibration_outcome.hpp"
#include "trainer/calibrate/calibration_result.hpp"
#include "trainer/calibrate/shared_dataset.hpp"
#include "trainer/data/inspection.hpp"
#include "trainer/data/sensor_fault.hpp"
#include "trainer/fleet/fleet_dump.hpp"
#include "trainer/lm/lm.hpp"
#include "trainer/lm/lm_result.hpp"
#include "trainer/model/motor_effects.hpp"
#include "trainer/model/motor_plausibility.hpp"
#include "trainer/search/search.hpp"
#include "trainer/workflow/calibration_adequacy.hpp"

namespace lptn::workflow {
namespace {

bool is_search(const std::string& method) { return method == "random-search" || method == "cma-es"; }

// The motor file with the request's effects switched on.
MotorFile requested_motor(const calibrate::CalibrationRequest& q) {
  MotorFile motor = load_motor_file(q.motor);
  for (const std::string& name : q.effects) enable_effect(motor, effect_by_name(name, "--effect"));
  return motor;
}

// What of the input makes the calibration doubtful, for its status: the data against the motor's
// nameplate (another pole count, a channel's scaling), the motor file's implausible values, and
// columns the loader ignored (a misnamed rotor column drops the rotor data). Gaps the loader bridged,
// masked or split as the data contract says are printed but make no calibration doubtful.
std::vector<std::string> doubtful_input(const data::Dataset& dataset, const MotorFile& motor) {
  std::vector<std::string> out;
  for (const data::CycleReport& r : dataset.reports)
    for (const data::Finding& f : r.findings)
      if (f.severity == data::Finding::Severity::warning && f.message.find("; ignored") != std::string::npos)
        out.push_back(f.message);
  for (const data::Finding& f : data::check_against_nameplate(dataset, motor.constants))
    if (f.severity == data::Finding::Severity::warning) out.push_back(f.message);
  for (std::string& w : motor_warnings(motor)) out.push_back(std::move(w));
  return out;
}

// The model ran away at the motor file's values: bad input, naming the most implausible value.
hostio::BadInput not_simulable(const std::string& path, const MotorFile& motor, const lm::ModelNotSimulable& e) {
  const std::string why = implausible_values_summary(motor);
  return hostio::BadInput(path + ": " + e.what() + (why.empty() ? std::string() : "; the most implausible value: " + why));
}

calibrate::CalibrationMethod method_for(const std::string& method, calibrate::CalibrationMethod td3) {
  if (method == "lm") return &lm::calibrate_lm;
  if (is_search(method)) return &search::calibrate_by_search;
  return td3;
}

}  // namespace

bool is_td3(const std::string& method) { return method == "td3" || method == "td3-paper" || method == "td3-episode"; }
bool is_method(const std::string& name) {
  for (std::string_view m : kMethods)
    if (m == name) return true;
  return false;
}

const hostio::ProcessGroup& calibration_group(const std::string& method) {
  return method == "lm" ? hostio::ProcessGroup::world() : hostio::ProcessGroup::alone();
}

void check_request(const calibrate::CalibrationRequest& q, calibrate::CalibrationMethod td3) {
  if (!is_method(q.method)) {
    std::string known;
    for (std::string_view m : kMethods) known += (known.empty() ? "" : ", ") + std::string(m);
    throw hostio::BadInput("--method " + q.method + ": not a calibration method (" + known + ")");
  }
  if (q.data.empty() && q.fleet.empty()) throw hostio::BadInput("calibrate: give --data (one motor) or --fleet (many)");
  if (!q.data.empty() && !q.fleet.empty()) throw hostio::BadInput("--data and --fleet: one or the other");
  if (!q.fleet.empty() && q.method != "lm")
    throw hostio::BadInput("--fleet: only --method lm calibrates a fleet (its per-motor factors are LM fits)");
  if (!q.fleet.empty() && !q.sensor_faults.empty()) throw hostio::BadInput("--sensor-fault: not with --fleet (a fault is one motor's sensor)");
  if ((!q.warm_start.empty() || q.test_curve) && q.method != "td3")
    throw hostio::BadInput(std::string(q.warm_start.empty() ? "--test-curve" : "--warm-start") + ": only with --method td3");
  // LM shares its work over the processes of an MPI job; TD3 does not: every rank would train the
  // same agent and write the same files.
  if (q.method != "lm" && hostio::launched_by_mpi())
    throw hostio::BadInput("--method " + q.method + ": not shared over MPI processes (only --method lm is); run it without mpirun");
  if (is_td3(q.method) && td3 == nullptr)
    throw hostio::BadInput("--method " + q.method + ": this program has no TD3 calibrator (lptn-td3 has; lptn runs it)");
  for (const std::string& name : q.effects) static_cast<void>(effect_by_name(name, "--effect"));
}

calibrate::CalibrationResult calibrate(const calibrate::CalibrationRequest& q, const CalibrationEvents& events, calibrate::CalibrationMethod td3) {
  check_request(q, td3);
  if (!q.fleet.empty()) throw hostio::BadInput("--fleet: a fleet is calibrated by calibrate_fleet");
  const hostio::ProcessGroup& group = calibration_group(q.method);
  MotorFile motor = requested_motor(q);
  std::vector<std::filesystem::path> paths(q.data.begin(), q.data.end());
  calibrate::SharedDataset dataset = calibrate::load_shared_dump(paths, group, data::with_data_map(q.map));
  try {
    data::correct_readings(dataset.data, q.sensor_faults);
  } catch (const hostio::BadInput& e) {
    throw hostio::BadInput(std::string("--sensor-fault: ") + e.what());
  }
  const calibrate::Split split = calibrate::split_cycles(dataset.data, q.test_cycles, q.test_fraction, q.seed);
  calibrate::balance_training(dataset, split.train, group);  // only LM runs shared
  if (events.input_warnings) events.input_warnings(input_warnings(dataset.data, motor));
  const std::vector<std::string> inspected = doubtful_input(dataset.data, motor);

  // LM judges what the data pins as it fits; the other methods would move a parameter the data
  // cannot see at random and call it calibrated: it stays the motor file's, said so.
  std::vector<lm::NotIdentifiable> unseen;
  try {
    if (q.method != "lm") unseen = lm::unseen_parameters(motor, motor.initial_values(), dataset, split.train);
  } catch (const lm::ModelNotSimulable& e) {
    throw not_simulable(q.motor, motor, e);
  }
  for (const lm::NotIdentifiable& n : unseen) motor.parameters[static_cast<std::size_t>(n.index)].calibrate = false;
  calibrate::CalibrationResult r = calibrate::new_calibration(motor, q.motor, dataset, split);
  r.sensor_faults = q.sensor_faults;
  lm::mark_not_identifiable(r, unseen);
  if (events.started) events.started({motor.name, q.method, split.train.size(), split.test.size(), split.rule, 0});
  try {
    method_for(q.method, td3)(q, motor, dataset, split, r, events.progress);
  } catch (const lm::ModelNotSimulable& e) {
    throw not_simulable(q.motor, motor, e);
  }
  const std::vector<calibrate::CalibrationWarning> inadequate = score_and_judge_adequacy(r, motor, dataset, split);
  calibrate::judge_outcome(r, inspected, inadequate);
  return r;
}

FleetCalibration calibrate_fleet(const calibrate::CalibrationRequest& q, const CalibrationEvents& events) {
  check_request(q);
  if (q.fleet.empty()) throw hostio::BadInput("calibrate_fleet: give --fleet");
  const hostio::ProcessGroup& group = calibration_group(q.method);
  const MotorFile motor = requested_motor(q);
  const fleet::FleetDump fleet = fleet::load_shared_fleet(q.fleet, group, data::with_data_map(q.map));
  const calibrate::Split split = calibrate::split_cycles(fleet.dataset.data, q.test_cycles, q.test_fraction, q.seed);
  FleetCalibration out;
  out.result = calibrate::new_calibration(motor, q.motor, fleet.dataset, split);
  out.cycles = fleet.dataset.data.cycles.size();
  if (events.started)
    events.started({motor.name, q.method, split.train.size(), split.test.size(), split.rule, fleet.motor_ids.size()});
  out.settings.lm.judge_identifiability = true;
  try {
    out.fit = fleet::fit_fleet(motor, fleet, split.train, out.settings, [&](const std::string& s) {
      if (events.progress) events.progress(s, true);
    });
  } catch (const lm::ModelNotSimulable& e) {
    throw not_simulable(q.motor, motor, e);
  }
  calibrate::CalibrationResult& r = out.result;
  lm::record_lm_fit(r, out.fit.shared, calibrate::FreeParameters::from_motor(motor), r.train_cycles, lm::to_json(out.settings.lm));
  r.seconds = out.fit.seconds;
  calibrate::score_calibration(r, motor, fleet.dataset, split);
  if (events.input_warnings) events.input_warnings(input_warnings(fleet.dataset.data, motor));
  calibrate::judge_outcome(r, doubtful_input(fleet.dataset.data, motor), fleet_adequacy(motor, fleet, out.fit), calibrate::TestVsTrain::not_judged);
  return out;
}

}  // namespace lptn::workflow
