// lptn inspect: load and check a fleet dump; the first thing to run on new data.
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tools/cli/commands.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/data/inspection.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::cli {

void add_inspect(CLI::App& app) {
  auto* cmd = app.add_subcommand("inspect", "Load and check a fleet dump: rates, coverage, gaps, warnings per cycle");
  struct Args {
    std::vector<std::string> data;
    std::string motor;
    bool json = false, strict = false;
    double dt = 0.1;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("--data", args->data, "Directories of cycle CSVs, or CSV files")->required()->expected(1, -1);
  cmd->add_option("--motor", args->motor, "Motor file: also check the data against the nameplate");
  cmd->add_option("--dt", args->dt, "Model step to resample to, s")->capture_default_str()->check(CLI::Range(0.001, 10.0));
  cmd->add_flag("--json", args->json, "Print the report as JSON");
  cmd->add_flag("--strict", args->strict, "Exit non-zero (1) if there is any warning");
  cmd->callback([args] {
    std::vector<std::filesystem::path> paths(args->data.begin(), args->data.end());
    data::LoadOptions options;
    options.dt_s = args->dt;
    const data::Dataset dataset = data::load_fleet_dump(paths, options);
    std::vector<data::Finding> motor_findings;
    if (!args->motor.empty()) {
      const MotorFile motor = load_motor_file(args->motor);
      const MotorConstants<double>& c = motor.constants;
      motor_findings = data::check_against_nameplate(
          dataset, {c.pole_pairs, c.rated_frequency_hz, c.rated_current_a, c.rated_voltage_v});
    }
    std::size_t warnings = dataset.warning_count();
    for (const auto& f : motor_findings) warnings += f.severity == data::Finding::Severity::warning;
    if (args->json) {
      nlohmann::json j = data::report_json(dataset);
      j["nameplate_findings"] = nlohmann::json::array();
      for (const auto& f : motor_findings)
        j["nameplate_findings"].push_back(
            {{"severity", f.severity == data::Finding::Severity::warning ? "warning" : "info"}, {"message", f.message}});
      j["warnings"] = warnings;
      std::printf("%s\n", j.dump(2).c_str());
    } else {
      std::printf("%s", data::format_report(dataset).c_str());
      if (!args->motor.empty()) {
        std::printf("checks against the nameplate of %s: %s\n", args->motor.c_str(),
                    motor_findings.empty() ? "nothing to report" : "");
        for (const auto& f : motor_findings)
          std::printf("  %s: %s\n", f.severity == data::Finding::Severity::warning ? "warning" : "info", f.message.c_str());
      }
    }
    if (args->strict && warnings > 0) throw std::runtime_error(std::to_string(warnings) + " warning(s) with --strict");
  });
}

}  // namespace lptn::cli
