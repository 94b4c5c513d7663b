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

#include "hostio/bad_input.hpp"
#include "trainer/diagnose/diagnosis_file.hpp"

namespace lptn::report {

// Bad input the report itself finds (a diagnosis file that is not `lptn diagnose --json`);
// one line. A BadInput, so that the command line reports it as bad input (exit 2).
class ReportInputError : public hostio::BadInput {
 public:
  using BadInput::BadInput;
};

struct ReportOptions {
  std::filesystem::path data;         // fleet dump: a directory of cycle CSVs or one CSV
  std::filesystem::path calibration;  // calibration.json
  std::filesystem::path diagnosis;    // lptn diagnose --json output; empty = none
  std::filesystem::path history;      // directory of calibration JSONs; empty = the calibration's own
  std::filesystem::path fleet;        // fleet.json for the Fleet section; empty = none. With data and
                                      // calibration empty, the page holds the Fleet section alone
  std::filesystem::path data_map;     // --map; empty = data.toml beside the CSVs, if any
};

// The diagnosis the page shows: diagnose::load_diagnosis (trainer/diagnose/diagnosis_file.hpp).
using diagnose::SavedCandidate;
using diagnose::SavedDiagnosis;

// Everything the page shows, as the JSON its script reads.
nlohmann::json report_data(const ReportOptions& options, const std::function<void(const std::string&)>& progress);

// The page: template, styles, dygraphs and the report's script inlined, `data` embedded.
std::string render_html(const nlohmann::json& data);

}  // namespace lptn::report
