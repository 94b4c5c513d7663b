// The diagnosis file (lptn diagnose --json, --json-out; docs/diagnosis.md): its one reader, beside
// its one writer (to_json in diagnose.hpp). lptn report reads it; the keys a reader knows are
// these, others are ignored; the verdict on the model, the drift and the sensor findings are kept
// as diagnose wrote them, for the page to read as they are.
#pragma once

#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "hostio/bad_input.hpp"

namespace lptn::diagnose {

// A diagnosis file that is not one: one line naming the file. A BadInput, so that the command line
// reports it as bad input (exit 2).
class DiagnosisFileError : public hostio::BadInput {
 public:
  using BadInput::BadInput;
};

// A diagnosis as lptn diagnose --json-out saved it.
// One candidate:
struct SavedCandidate {
  std::string effect;
  std::string kind = "library";  // "library", "term", "drift" or "sensor"
  std::string words;             // in physical words with the refit's values
  std::string verdict;
  double statistic = std::numeric_limits<double>::quiet_NaN();
  double threshold = std::numeric_limits<double>::quiet_NaN();
  double predicted_rmse_k = std::numeric_limits<double>::quiet_NaN();
  double refit_rmse_k = std::numeric_limits<double>::quiet_NaN();
  double test_rmse_k_before = std::numeric_limits<double>::quiet_NaN();
  double test_rmse_k_after = std::numeric_limits<double>::quiet_NaN();
  bool significant = false;
  bool recommended = false;
  std::vector<std::pair<std::string, double>> parameters;  // the refit's values by parameter name
  std::vector<std::pair<std::string, double>> refit_values;  // every parameter after the refit, where given
};
struct SavedDiagnosis {
  double rmse_k = std::numeric_limits<double>::quiet_NaN();
  std::vector<SavedCandidate> candidates;
  // The verdict on the model itself and the drift between cycles, as diagnose wrote them (null in
  // a diagnosis from before they existed); the page reads them as they are.
  nlohmann::json adequacy;  // {"adequate", "sensors"}
  nlohmann::json drift;
  nlohmann::json sensor_faults;  // [{"sensor", "found", "finding", ...}] (sensor_check.hpp)
};
// Reads what to_json (diagnose.hpp) wrote, of format 1 to kDiagnosisFormatVersion. Throws
// DiagnosisFileError, one line naming the file (and the candidate), where it is not JSON, lacks
// "candidates", is of a newer format, or a candidate is malformed; JsonFileError where it cannot be
// read.
SavedDiagnosis load_diagnosis(const std::filesystem::path& path);

}  // namespace lptn::diagnose
