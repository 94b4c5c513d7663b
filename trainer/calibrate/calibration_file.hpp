// calibration.json: what a calibration found, how, from which data, and how well it fits.
// The key reference is docs/calibration.md; keys are stable (tests and the report read them).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "hostio/json_file.hpp"
#include "lptn/model.hpp"
#include "trainer/calibrate/metrics.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::calibrate {

// Bumped whenever a key changes meaning; a reader refuses versions it does not know. Version 1 is
// read as "unchecked" (it had no status and marked every free parameter calibrated, pinned by the
// data or not); versions 1 and 2 carried the motor as its TOML text only, which the reader parses.
inline constexpr int kCalibrationFormatVersion = 3;
inline constexpr int kOldestReadCalibrationFormatVersion = 1;

// A bad calibration file; one line: "FILE: field 'a.b[3].c': reason" or "FILE: line N: reason".
using CalibrationFileError = hostio::JsonFileError;

struct ParameterResult {
  std::string name;  // as in param_spec(); the vector below is in the model's fixed parameter order
  std::string unit;
  double value = 0;     // the calibrated value (or the fixed one where calibrated == false)
  double initial = 0;   // where the calibrator started
  double min = 0, max = 0;
  bool calibrated = false;
  double std_error = std::numeric_limits<double>::quiet_NaN();  // LM only; NaN where unknown
  // Whether the data pinned it (LM judges; other methods leave it true). A parameter the data
  // cannot pin is left at the motor file's value, calibrated = false, with the reason in words.
  bool identifiable = true;
  std::string identifiability;  // empty where identifiable
};

// Something a user must know about a calibration before using it (docs/calibration.md lists the
// codes): a parameter at a bound, one the data could not pin, a fit that did not converge...
struct CalibrationWarning {
  std::string code;                     // stable, e.g. "at_bound", "not_identifiable"
  std::string message;                  // one line, in words
  std::vector<std::string> parameters;  // the parameters it concerns (may be empty)
};

// The calibration's outcome: ok (use it), warnings (written; read them first), failed (written
// for inspection only; lptn export refuses it), unchecked (a version-1 file, made before lptn
// judged outcomes).
inline constexpr const char* kStatusOk = "ok";
inline constexpr const char* kStatusWarnings = "warnings";
inline constexpr const char* kStatusFailed = "failed";
inline constexpr const char* kStatusUnchecked = "unchecked";

// A parameter pair the data cannot tell apart (LM): |correlation| at or above the flag threshold.
struct CorrelatedPair {
  std::string a, b;
  double correlation = 0;
};

// One dense layer, y = W x + b, W row-major (out rows of in columns).
struct ActorLayer {
  int in = 0, out = 0;
  std::vector<float> weight;
  std::vector<float> bias;
};

// The frozen TD3 actor: observation -> normalized parameters in [-1, 1] -> physical values.
// obs_i = (raw_i - obs_offset_i) / obs_scale_i with raw = {speed_rpm, torque_nm}; layers with
// ReLU between them and tanh after the last; output j drives parameter param_indices[j] through
// from_normalized(u, min, max) with that parameter's bounds (ParameterResult::min/max).
struct ActorExport {
  std::array<double, 2> obs_offset{0, 0};
  std::array<double, 2> obs_scale{1, 1};
  std::vector<ActorLayer> layers;
  std::vector<int> param_indices;
  // libtorch's own output for a few observations, kept so that any other forward pass (the
  // exported header's) can prove it matches: check_obs is n x 2 (normalized), check_actions n x P
  // (tanh outputs, before scaling).
  std::vector<float> check_obs;
  std::vector<float> check_actions;
};

struct DataFile {
  std::string cycle;  // cycle name
  std::string file;   // file name as given
  std::string sha256;  // of the file's bytes
  // The data map the file was read through (data::Cycle::map_file, map_sha256; both empty: read as
  // lptn's own CSV). Not recorded in a calibration file older than this field: nothing to compare.
  bool map_recorded = true;
  std::string map_file{}, map_sha256{};  // initialised here: {cycle, file, sha256} alone is a whole record
};

struct CalibrationResult {
  int format_version = kCalibrationFormatVersion;
  std::string created_utc;   // ISO 8601, e.g. "2026-11-21T10:00:00Z"
  std::string lptn_version;  // "lptn 0.1.0"

  // The motor file the calibration started from, whole, so that the result alone rebuilds the
  // model: its constants, parameter settings and effects (motor.json in the file), its path as given
  // and its text as read (provenance only: from format 3 on, nothing parses it).
  MotorFile motor;
  EffectSet effects = 0;  // the model's: the motor file's and those added since (calibrate --add, diagnose)

  std::vector<ParameterResult> parameters;  // kNumParams entries, model order
  std::vector<CorrelatedPair> correlated;   // LM only

  std::string status = kStatusOk;  // kStatus*: what the warnings add up to (calibration_outcome.hpp)
  std::vector<CalibrationWarning> warnings;

  std::string method;         // "lm", "td3" (the paper's per-step formulation) or "td3-episode"
  nlohmann::json settings;    // the method's settings as used (free form, method-specific)
  nlohmann::json details;     // what the run reported: iterations, cost, training curve, seconds...
  double seconds = 0;         // wall time of the calibration itself

  std::vector<DataFile> data;  // every file the run read, train and test
  std::string data_sha256;     // over the per-file hashes in cycle order
  std::vector<std::string> train_cycles, test_cycles;
  std::string split_rule;      // "--test-cycles a,b" or "fraction 0.33, seed 1"
  // Sensor faults taken out of the readings before the fit (lptn calibrate --sensor-fault,
  // trainer/data/sensor_fault.hpp): whoever compares this calibration with that data corrects them too.
  std::vector<std::string> sensor_faults;

  SplitMetrics train, test;

  bool has_actor = false;
  ActorExport actor;

  ParamVector<double> values() const;  // parameters[i].value in model order
};

nlohmann::json to_json(const CalibrationResult& result);
// One side of the split as calibration.json writes it (the pooled figures, then each cycle's).
nlohmann::ordered_json split_metrics_json(const SplitMetrics& m);
CalibrationResult calibration_from_json(const nlohmann::json& j, const std::string& shown_as);

// Atomic: a temporary beside `path`, renamed over it.
void save_calibration(const CalibrationResult& result, const std::filesystem::path& path);
CalibrationResult load_calibration(const std::filesystem::path& path);
// A JSON file lptn wrote (calibration.json, fleet.json); throws CalibrationFileError: "FILE: cannot
// read (...)", "FILE: line N: reason", or, for a motor file or a cycle given in its place, what it is.
nlohmann::json read_lptn_json(const std::filesystem::path& path);

}  // namespace lptn::calibrate
