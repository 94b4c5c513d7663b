// lptn inspect: load and check a fleet dump; the first thing to run on new data.
#include <algorithm>
#include <cmath>
#include <memory>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "can/canfile/can_log.hpp"
#include "can/canlog/convert.hpp"
#include "programs/cli/bus_option.hpp"
#include "programs/cli/commands.hpp"
#include "programs/cli/data_map_option.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/data/inspection.hpp"
#include "trainer/data/suggest_map.hpp"
#include "trainer/model/motor_file.hpp"
#include "trainer/model/motor_plausibility.hpp"

namespace lptn::cli {

void add_inspect(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "inspect", "Load and check a fleet dump (or CAN logs, decoded): rates, coverage, gaps, warnings per cycle");
  struct Args {
    std::vector<std::string> data, logs;
    std::string motor, map, bus, format;
    bool json = false, strict = false, suggest_map = false;
    double dt = 0.1;
  };
  auto args = std::make_shared<Args>();
  auto* data = cmd->add_option("--data", args->data, "Directories of cycle CSVs, or CSV files")->expected(1, -1);
  auto* logs = cmd->add_option("--log", args->logs,
                               "CAN logs (candump -L, Vector ASC, BLF, MDF4): decoded through the DBC (or --bus) into "
                               "the channels, as lptn convert would, then checked as a cycle CSV is")
                   ->expected(1, -1);
  cmd->add_option("--bus", args->bus, "With --log: the converter's frames (bus.toml) instead of lptn's own TC_* frames");
  cmd->add_option("--format", args->format, "With --log: the logs' format, candump, asc, blf or mdf4 (default: by extension or content)")
      ->check(CLI::IsMember({"candump", "asc", "blf", "mdf4"}));
  cmd->add_option("--motor", args->motor,
                  "Motor file: also check the data against its nameplate, and its values against the same nameplate");
  cmd->add_option("--dt", args->dt, "Model step to resample to, s")->capture_default_str()->check(CLI::Range(0.001, 10.0));
  add_map_option(cmd, args->map);
  cmd->add_flag("--json", args->json, "Print the report as JSON");
  cmd->add_flag("--strict", args->strict, "Exit non-zero (1) if there is any warning");
  cmd->add_flag("--suggest-map", args->suggest_map,
                "Print a proposed data map (data.toml) for an export lptn cannot read as it is: columns matched by name "
                "and by their values, separator, decimal mark and time column detected; only the map on standard "
                "output, what to check on standard error; exit 1 when a required column was not found");
  cmd->callback([args, data, logs] {
    if (data->count() == 0 && logs->count() == 0) throw hostio::BadInput("inspect: give --data (cycle CSVs) or --log (CAN logs)");
    if (args->suggest_map && data->count() == 0) throw hostio::BadInput("--suggest-map: give --data, the export's CSV files");
    for (const std::string& d : args->data) check_input_path(d, "--data");
    for (const std::string& l : args->logs) check_input_path(l, "--log", InputPath::file);
    if (!args->motor.empty()) check_input_path(args->motor, "--motor", InputPath::file);
    std::optional<model::MotorFile> motor;
    if (!args->motor.empty()) motor = model::load_motor_file(args->motor);
    std::vector<std::filesystem::path> paths(args->data.begin(), args->data.end());
    if (args->suggest_map) {
      data::SuggestHints hints;
      if (motor) {
        hints.pole_pairs = motor->constants.pole_pairs;
        hints.rated_current_a = motor->constants.rated_current_a;
        hints.rated_voltage_v = motor->constants.rated_voltage_v;
        hints.nominal_airflow_m3s = motor->constants.nominal_airflow_m3s;
      }
      const data::MapSuggestion s = data::suggest_data_map(paths, hints);
      std::printf("%s", s.text().c_str());
      for (const std::string& p : s.problems) std::fprintf(stderr, "lptn: check the map: %s\n", p.c_str());
      const bool incomplete = std::any_of(s.problems.begin(), s.problems.end(), [](const std::string& p) {
        return p.find("(required)") != std::string::npos || p.find("no time column") != std::string::npos;
      });
      if (incomplete) throw std::runtime_error("the proposed map lacks a required column; edit it before use");
      return;
    }
    data::LoadOptions options;
    options.dt_s = args->dt;
    options = with_map(args->map, options);
    data::Dataset dataset = paths.empty() ? data::Dataset{} : data::load_fleet_dump(paths, options);
    if (!args->logs.empty()) {
      const std::unique_ptr<bus::BusMap> bus = args->bus.empty() ? nullptr : read_bus_map(args->bus);
      std::optional<canfile::LogFormat> format;
      if (!args->format.empty()) format = canfile::format_from_name(args->format);
      for (const std::string& log : args->logs) {
        const canlog::Converted converted = canlog::csv_from_log(log, {format, ""}, bus.get());
        data::LoadOptions from_log = options;
        from_log.map = nullptr;  // decoded into lptn's own columns
        from_log.map_beside = false;
        data::Dataset one = data::parse_cycle_csv(converted.text, log, from_log);
        auto& findings = one.reports.front().findings;
        findings.insert(findings.begin(), {data::Finding::Severity::info,
                                           log + ": " + std::to_string(converted.frames) + " frames decoded over " +
                                               std::to_string(static_cast<long long>(std::llround(converted.duration_s))) +
                                               " s"});
        for (const std::string& w : converted.warnings) findings.push_back({data::Finding::Severity::warning, w});
        for (data::Cycle& c : one.cycles) dataset.cycles.push_back(std::move(c));
        for (data::CycleReport& r : one.reports) dataset.reports.push_back(std::move(r));
      }
    }
    std::vector<data::Finding> nameplate_findings;
    std::vector<model::MotorFinding> motor_findings;
    if (motor) {
      nameplate_findings = data::check_against_nameplate(dataset, motor->constants);
      motor_findings = model::check_motor_plausibility(*motor);
    }
    std::size_t warnings = dataset.warning_count() + motor_findings.size();
    for (const auto& f : nameplate_findings) warnings += f.severity == data::Finding::Severity::warning;
    if (args->json) {
      nlohmann::json j = data::report_json(dataset);
      j["nameplate_findings"] = nlohmann::json::array();
      for (const auto& f : nameplate_findings)
        j["nameplate_findings"].push_back(
            {{"severity", f.severity == data::Finding::Severity::warning ? "warning" : "info"}, {"message", f.message}});
      // Each implausible value of the motor file, with the range its own nameplate makes plausible.
      j["motor_findings"] = nlohmann::json::array();
      for (const model::MotorFinding& f : motor_findings)
        j["motor_findings"].push_back({{"severity", "warning"},
                                       {"key", f.key},
                                       {"value", f.value},
                                       {"line", f.line},
                                       {"message", model::format_motor_finding(*motor, f)},
                                       {"plausible", f.plausible}});
      j["warnings"] = warnings;
      std::printf("%s\n", j.dump(2).c_str());
    } else {
      std::printf("%s", data::format_report(dataset).c_str());
      if (motor) {
        std::printf("checks against the nameplate of %s: %s\n", args->motor.c_str(),
                    nameplate_findings.empty() ? "nothing to report" : "");
        for (const auto& f : nameplate_findings)
          std::printf("  %s: %s\n", f.severity == data::Finding::Severity::warning ? "warning" : "info", f.message.c_str());
        std::printf("the motor file's values against its nameplate: %s\n",
                    motor_findings.empty() ? "all plausible" : "");
        for (const model::MotorFinding& f : motor_findings)
          std::printf("  warning: %s\n", model::format_motor_finding(*motor, f).c_str());
      }
    }
    if (args->strict && warnings > 0) throw std::runtime_error(std::to_string(warnings) + " warning(s) with --strict");
  });
}

}  // namespace lptn::cli
