// lptn diagnose: is the calibrated model adequate, and which effect of the library or term of the
// dictionary it lacks, with --auto forward selection over them. The work is trainer/workflow's and
// the words trainer/diagnose's (diagnosis_text); this file reads the arguments, prints and writes.
#include <chrono>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "hostio/atomic_file.hpp"
#include "hostio/process_group.hpp"
#include "hostio/progress_line.hpp"
#include "programs/cli/commands.hpp"
#include "programs/cli/data_map_option.hpp"
#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/diagnose/diagnosis_text.hpp"
#include "trainer/workflow/diagnose.hpp"

namespace lptn::cli {
namespace {

struct DiagnoseArgs {
  workflow::DiagnosisRequest request;
  std::string out, json_out;
  bool json = false, force = false, quiet = false;
};

void run(const DiagnoseArgs& given) {
  // Under mpirun every rank diagnoses (the LM refits are shared); rank 0 alone speaks and writes.
  const hostio::ProcessGroup& group = hostio::ProcessGroup::world();
  DiagnoseArgs a = given;
  a.request.updated_calibration = !a.out.empty();
  const workflow::DiagnosisRequest& q = a.request;
  if (!group.leads()) {
    a.quiet = true;
    if (std::freopen("/dev/null", "w", stdout) == nullptr) throw std::runtime_error("cannot silence rank " + std::to_string(group.rank()));
  }
  if (!a.out.empty() && !q.automatic) throw hostio::BadInput("--out: only with --auto (the calibration after forward selection)");
  // Inputs, then the outputs, before any work (a missing input is the first thing to hear of).
  for (const std::string& d : q.data) check_input_path(d, "--data");
  check_input_path(q.calibration, "--calibration", InputPath::file);
  if (!q.map.empty()) check_input_path(q.map, "--map", InputPath::file);
  check_output_path(a.out, a.force);
  check_output_path(a.json_out, a.force, "--json-out");

  const auto t0 = std::chrono::steady_clock::now();
  hostio::ProgressLine line(a.quiet);
  workflow::DiagnosisEvents events;
  events.input_warnings = [&group](const std::vector<std::string>& warnings) {
    if (group.leads()) print_input_warnings(warnings);
  };
  events.started = [&a](const workflow::DiagnosisPlan& p) {
    if (!a.json) {
      std::printf("diagnosing %s (effects: %s) on %zu training cycles, testing on %zu\n", p.motor_name.c_str(),
                  diagnose::effect_list(p.effects).c_str(), p.train_cycles, p.test_cycles);
      std::printf("before, as the calibration file has it (on the data it was fitted on): %s\n", p.calibration_figures.c_str());
      for (const std::string& c : p.corrections) std::printf("%s\n", c.c_str());
      if (!p.not_its_data.empty()) std::printf("%s\n", p.not_its_data.c_str());
    }
    std::fflush(stdout);  // before the progress lines on stderr
  };
  events.progress = [&](const std::string& text) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    line.update("diagnose: " + text + "  " + hostio::ProgressLine::clock(s));
  };
  int round = 0;
  if (q.automatic)
    events.round_done = [&](const diagnose::Diagnosis& d) {
      line.finish();
      if (a.json) return;
      std::printf("\nround %d\n", ++round);
      std::fputs(diagnose::diagnosis_text(d, q.level).c_str(), stdout);
      std::fflush(stdout);
    };
  const workflow::DiagnosisOutcome o = workflow::diagnose(q, events);
  line.finish();
  if (!a.json_out.empty() && group.leads()) hostio::write_file_atomically(a.json_out, o.json.dump(2) + "\n");
  if (a.json) std::printf("%s\n", o.json.dump(2).c_str());
  else if (!q.automatic) std::fputs(diagnose::diagnosis_text(o.last(), q.level).c_str(), stdout);
  else {
    std::string added;
    for (const std::string& name : o.added) added += (added.empty() ? "" : ", ") + name;
    std::printf("\nforward selection added: %s\n", added.empty() ? "nothing" : added.c_str());
  }
  if (a.out.empty() || !o.updated || !group.leads()) return;
  calibrate::save_calibration(*o.updated, a.out);
  if (!a.json) std::printf("%s written (effects: %s)\n", a.out.c_str(), diagnose::effect_list(o.updated->effects).c_str());
}

}  // namespace

void add_diagnose(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "diagnose", "Is the calibrated model adequate, did the motor drift between cycles, and which effect of the library or "
                  "term of the dictionary does it lack (score test, refit, block test, held-out error); under `mpirun -np N` "
                  "its LM refits are shared over N processes");
  auto a = std::make_shared<DiagnoseArgs>();
  cmd->add_option("--data", a->request.data, "Directories of cycle CSVs, or CSV files (the data the calibration was made from)")
      ->required()
      ->expected(1, -1);
  cmd->add_option("--calibration", a->request.calibration, "calibration.json (from lptn calibrate)")->required();
  add_map_option(cmd, a->request.map);
  cmd->add_option("--test-cycles", a->request.test_cycles, "Cycles held out for testing, by name (default: the calibration's split)")
      ->delimiter(',');
  cmd->add_option("--level", a->request.level, "False-alarm probability of the likelihood-ratio test per effect (default 0.001)");
  cmd->add_flag("--json", a->json, "Print the diagnosis as JSON: {\"rmse_k\", \"candidates\": [...]}, best first");
  cmd->add_option("--json-out", a->json_out, "Also write that JSON to this file (for lptn report --diagnosis)");
  cmd->add_flag("--auto", a->request.automatic, "Forward selection: add the best significant effect, refit, repeat until none is");
  cmd->add_option("--out", a->out, "With --auto: write the final calibration here");
  cmd->add_flag("--force", a->force, "Replace --out and --json-out if they exist");
  cmd->add_flag("--quiet", a->quiet, "No progress output");
  cmd->callback([a] { run(*a); });
}

}  // namespace lptn::cli
