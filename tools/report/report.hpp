// lptn report: one self-contained HTML file on how a calibration fits a fleet dump (Compare),
// where it fails (operating regions, worst windows, correlations), what lptn diagnose says is
// missing, and how the error fell from calibration to calibration (History).
#pragma once

#include <filesystem>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace lptn::report {

// Bad input the report itself finds (a diagnosis file that is not `lptn diagnose --json`);
// one line. An invalid_argument, so that the command line reports it as bad input (exit 2).
class ReportInputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

struct ReportOptions {
  std::filesystem::path data;         // fleet dump: a directory of cycle CSVs or one CSV
  std::filesystem::path calibration;  // calibration.json
  std::filesystem::path diagnosis;    // lptn diagnose --json output; empty = none
  std::filesystem::path history;      // directory of calibration JSONs; empty = the calibration's own
  std::filesystem::path fleet;        // fleet.json for the Fleet section; empty = none. With data and
                                      // calibration empty, the page holds the Fleet section alone
};

// A diagnosis as lptn diagnose --json-out saved it (the keys the report knows; others are ignored).
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
// Throws ReportInputError naming the file when it is not JSON or lacks "candidates".
SavedDiagnosis load_diagnosis(const std::filesystem::path& path);

// Everything the page shows, as the JSON its script reads.
nlohmann::json report_data(const ReportOptions& options, const std::function<void(const std::string&)>& progress);

// The page: template, styles, dygraphs and the report's script inlined, `data` embedded.
std::string render_html(const nlohmann::json& data);

}  // namespace lptn::report
