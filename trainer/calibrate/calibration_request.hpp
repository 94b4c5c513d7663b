// What a calibration is asked to do (the data, the motor, the method and its settings, the split),
// and the one signature every method runs under: LM (trainer/lm), the search baselines
// (trainer/search) and TD3 (trainer/td3, libtorch) each fill in the result's parameters, method,
// settings and details themselves. trainer/workflow takes a request to a scored, judged calibration;
// a command line, a notebook binding or a service only fills in the request.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/calibrate/shared_dataset.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::calibrate {

struct CalibrationRequest {
  std::vector<std::string> data;  // directories of cycle CSVs, or CSV files
  std::string fleet;              // or a fleet: FLEET/<motor_id>/*.csv, one motor type (LM only)
  std::string map;                // the data map (TOML); empty: data.toml beside the CSVs
  std::string motor;              // the motor file
  std::string method = "lm";      // lm, td3, td3-paper, td3-episode, random-search, cma-es
  std::vector<std::string> effects;        // switched on besides the motor file's, by library name
  std::vector<std::string> sensor_faults;  // SENSOR:SHAPE:SIZE:FIRST, taken out of the readings first
  std::vector<std::string> test_cycles;    // held out by name; else test_fraction of them, drawn with seed
  double test_fraction = 1.0 / 3.0;
  std::uint64_t seed = 1;  // the split's and TD3's
  bool seed_given = false;  // TD3: the seed wins over its settings file's
  std::size_t budget_steps = 0;  // random-search, cma-es: model steps to spend (0: their default)
  // TD3's own.
  std::string td3_config;      // settings (TOML); empty: the formulation's defaults
  std::string checkpoint_dir;  // empty: OUT.checkpoints
  std::string warm_start;      // an earlier td3 calibration whose agent to start from
  int episodes = 0;            // stop after this many (0: the settings' max_episodes)
  bool resume = false, test_curve = false;
  // Where the calibration will be written (TD3 keeps its agent and checkpoints beside it).
  std::string out;
};

// A line of progress; `done`: the step it reports is over (a log keeps that line).
using CalibrationProgress = std::function<void(const std::string& line, bool done)>;

// A calibration method: fits `motor`'s free parameters on `split.train` of `dataset` (shared over the
// processes of an MPI job where the method shares its work: LM; the others get it whole) and records
// in `result` the values, the method's name, settings and details and its wall time (metrics and
// status are the workflow's). Throws BadInput for a request it cannot run.
using CalibrationMethod = void (*)(const CalibrationRequest& request, const MotorFile& motor, DatasetRef dataset,
                                   const Split& split, CalibrationResult& result, const CalibrationProgress& progress);

}  // namespace lptn::calibrate
