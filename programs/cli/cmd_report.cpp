// lptn report: one self-contained HTML page on a calibration against a fleet dump.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "programs/cli/commands.hpp"
#include "programs/cli/data_map_option.hpp"
#include "hostio/progress_line.hpp"
#include "tools/report/report.hpp"
#include "hostio/atomic_file.hpp"

namespace lptn::cli {

void add_report(CLI::App& app) {
  auto* cmd = app.add_subcommand("report", "Write an HTML report: model against measurements, where it fails, "
                                           "what lptn diagnose says is missing, the calibration history");
  struct Args {
    std::string data, calibration, out, diagnosis, history, fleet, map;
    bool force = false;
  };
  auto a = std::make_shared<Args>();
  auto* data_option = cmd->add_option("--data", a->data, "Fleet dump: a directory of cycle CSVs, or one CSV");
  auto* calibration_option = cmd->add_option("--calibration", a->calibration, "calibration.json (lptn calibrate)");
  add_map_option(cmd, a->map);
  data_option->needs(calibration_option);
  calibration_option->needs(data_option);
  cmd->add_option("--fleet", a->fleet,
                  "fleet.json (lptn calibrate --fleet): adds the Fleet section (each motor's cooling factor, the "
                  "outliers); alone, a page of the fleet only");
  cmd->add_option("--out", a->out, "The report, one HTML file that opens offline")->required();
  cmd->add_option("--diagnosis", a->diagnosis, "lptn diagnose --json output, for the 'What is missing' section");
  cmd->add_option("--history", a->history,
                  "Directory of calibration JSONs for the 'History' section (default: the calibration's directory)");
  cmd->add_flag("--force", a->force, "Replace --out if it exists");
  cmd->callback([a] {
    if (a->data.empty() && a->fleet.empty()) throw hostio::BadInput("report: give --data and --calibration, or --fleet");
    // Inputs, then the output, before any work (a missing input is the first thing to hear of).
    if (!a->data.empty()) check_input_path(a->data, "--data");
    if (!a->calibration.empty()) check_input_path(a->calibration, "--calibration", InputPath::file);
    if (!a->fleet.empty()) check_input_path(a->fleet, "--fleet", InputPath::file);
    if (!a->diagnosis.empty()) check_input_path(a->diagnosis, "--diagnosis", InputPath::file);
    if (!a->map.empty()) check_input_path(a->map, "--map", InputPath::file);
    check_output_path(a->out, a->force);
    if (!a->calibration.empty() && !std::filesystem::exists(a->calibration)) throw hostio::BadInput(a->calibration + ": no such file");
    if (!a->fleet.empty() && !std::filesystem::exists(a->fleet)) throw hostio::BadInput(a->fleet + ": no such file");
    if (!a->history.empty() && !std::filesystem::is_directory(a->history))
      throw hostio::BadInput(a->history + ": not a directory");
    const auto start = std::chrono::steady_clock::now();
    std::string html;
    {
      hostio::ProgressLine progress;
      const nlohmann::json data = report::report_data({a->data, a->calibration, a->diagnosis, a->history, a->fleet, a->map},
                                                      [&](const std::string& s) { progress.update("report: " + s); });
      html = report::render_html(data);
    }
    hostio::write_file_atomically(a->out, html);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("report written to %s (%.1f MB, %.1f s)\n", a->out.c_str(), static_cast<double>(html.size()) / 1e6, seconds);
  });
}

}  // namespace lptn::cli
