// lptn diagnose: which effect of the library the calibrated model lacks (trainer/diagnose/), and
// with --auto forward selection over them.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "programs/cli/commands.hpp"
#include "hostio/utc_stamp.hpp"
#include "programs/cli/data_map_option.hpp"
#include "trainer/model/motor_plausibility.hpp"
#include "hostio/process_group.hpp"
#include "hostio/progress_line.hpp"
#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/calibrate/shared_dataset.hpp"
#include "trainer/check/provenance.hpp"
#include "trainer/check/sensor_corrections.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/diagnose/diagnose.hpp"
#include "hostio/atomic_file.hpp"

namespace lptn::cli {
namespace {

struct DiagnoseArgs {
  std::vector<std::string> data;
  std::string calibration, out, json_out, map;
  std::vector<std::string> test_cycles;
  double level = 0.001;
  bool json = false, automatic = false, force = false, quiet = false;
};

std::string effect_list(EffectSet effects) {
  std::string out;
  for (int e = 0; e < kNumEffects; ++e)
    if (effects & effect_bit(e)) out += (out.empty() ? "" : ", ") + std::string(EffectLibrary::kNames[e]);
  return out.empty() ? "none" : out;
}

// "1.234" or "-" where there is no figure (no test cycles).
std::string kelvin(double v) {
  if (!std::isfinite(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", v);
  return buf;
}

// "0.981..1.012": the spread of the per-cycle factors.
std::string factor_range(const diagnose::Drift& drift) {
  if (drift.factors.empty()) return "-";
  double lo = drift.factors.front().factor, hi = lo;
  for (const diagnose::CycleFactor& f : drift.factors) lo = std::min(lo, f.factor), hi = std::max(hi, f.factor);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3f..%.3f", lo, hi);
  return buf;
}

std::string joined(const std::vector<std::string>& v) {
  std::string out;
  for (const std::string& x : v) out += (out.empty() ? "" : " ") + x;
  return out;
}

// "before" as the calibration file has it, whatever the data given: its own figures on its own data.
std::string file_figures(const CalibrationResult& c) {
  auto side = [](const char* name, const SplitMetrics& m) {
    std::string out = std::string(name) + " stator " + (m.stator.samples ? kelvin(m.stator.rmse_k) : "-") + " K";
    if (m.rotor.samples) out += ", rotor " + kelvin(m.rotor.rmse_k) + " K";
    return out;
  };
  return side("train", c.train) + "; " + side("test", c.test);
}

nlohmann::json file_figures_json(const CalibrationResult& c) {
  auto number = [](const ErrorMetrics& m) { return m.samples ? nlohmann::json(m.rmse_k) : nlohmann::json(nullptr); };
  return {{"train", {{"rmse_stator_k", number(c.train.stator)}, {"rmse_rotor_k", number(c.train.rotor)}}},
          {"test", {{"rmse_stator_k", number(c.test.stator)}, {"rmse_rotor_k", number(c.test.rotor)}}}};
}

// The data's relation to the calibration and what diagnose did with it, for --json: the figures
// the calibration file has, whether this is its data, and that the baseline is a refit.
nlohmann::json provenance_json(const CalibrationResult& c, const check::Provenance& p, const diagnose::Diagnosis& d) {
  return {{"calibration_figures", file_figures_json(c)},
          {"calibration_data", p.all_seen()},
          {"never_seen", p.unseen_names()},
          {"constants", p.constants},
          {"summary", p.summary()},
          {"refit", true},
          {"refit_iterations", d.baseline.iterations}};
}

// Where nothing explains the residual: what its shape suggests, per sensor that is not adequate.
void print_shapes(const diagnose::Diagnosis& d) {
  for (const diagnose::SensorAdequacy& s : d.adequacy.sensors)
    if (const std::string words = diagnose::shape_in_words(s); !words.empty())
      std::printf("  what the shape suggests: %s.\n", words.c_str());
}

void print_table(const diagnose::Diagnosis& d, double level) {
  std::printf("the baseline refit from the calibration's values (%d LM iterations) on the training cycles: "
              "training RMSE %.3f K (stator %s K), test stator %s K; %.0f effective residuals (correlation time %.1f steps)\n",
              d.baseline.iterations, d.rmse_k, kelvin(d.train_stator_rmse_k).c_str(), kelvin(d.test_stator_rmse_k).c_str(),
              d.effective_residuals, d.baseline.correlation_time);
  std::printf("the model against its sensors' noise (adequate within %.1fx):\n", diagnose::kAdequateRatio);
  for (const diagnose::SensorAdequacy& s : d.adequacy.sensors) std::printf("  %s\n", diagnose::describe(s).c_str());
  const diagnose::SensorFinding* const fault = d.sensor_fault();
  for (const diagnose::SensorFinding& s : d.sensors)
    if (s.found)
      std::printf("SENSOR FAULT: %s.\n  Inspect %s. Nothing is recommended while a sensor reads wrong: an effect "
                  "would absorb the fault.\n", s.finding.c_str(), s.inspect.c_str());
    else
      std::printf("no %s sensor fault: %s\n", data::sensor_name(s.sensor), s.finding.c_str());
  if (d.drift.found)
    std::printf("drift between cycles: %s.\n  Inspect %s. Nothing is recommended while the dump drifts: an effect "
                "would absorb the change.\n", d.drift.finding.c_str(), d.drift.inspect.c_str());
  else if (fault && !d.drift.finding.empty())
    std::printf("no drift of the motor between cycles: %s\n", d.drift.finding.c_str());
  else
    std::printf("no drift between cycles (per-cycle %s factors %s, p = %.2f)\n", diagnose::to_string(d.drift.group),
                factor_range(d.drift).c_str(), d.drift.p_value);
  if (d.candidates.empty()) {
    std::printf("every effect of the library and term of the dictionary is already in the model%s\n",
                d.adequacy.adequate ? "" : ", and something is still missing: it is none of them");
    if (!fault && !d.drift.found) print_shapes(d);
    return;
  }
  std::printf("%-34s %10s %9s %21s %21s %21s  %s\n", "effect or term", "score", "pred. K", "LR / threshold",
              "train K before->after", "held-out K bef.->aft.", "verdict");
  for (const diagnose::Candidate& c : d.candidates) {
    char lr[32], train[40], test[40];
    std::snprintf(lr, sizeof lr, "%.1f / %.1f", c.statistic, c.threshold);
    std::snprintf(train, sizeof train, "%.3f -> %.3f", d.rmse_k, c.refit_rmse_k);
    // Held out: both sensors (a candidate that helps one sensor and hurts the other shows here).
    std::snprintf(test, sizeof test, "%s -> %s", kelvin(d.test_rmse_k).c_str(), kelvin(c.test_rmse_k_after).c_str());
    std::printf("%-34s %10.1f %9.3f %21s %21s %21s  %s\n", c.name.c_str(), c.score, c.predicted_rmse_k, lr, train, test,
                diagnose::to_string(c.verdict));
  }
  for (const diagnose::Candidate& c : d.candidates)
    if (c.kind == EffectKind::term) std::printf("  %s: %s\n", c.name.c_str(), c.words.c_str());
  if (!d.term_scores.empty()) {
    std::printf("  dictionary: %zu terms scored; best scores", d.term_scores.size());
    for (std::size_t i = 0; i < d.term_scores.size() && i < 5; ++i)
      std::printf("%s %s %.1f", i ? "," : "", d.term_scores[i].name.c_str(), d.term_scores[i].score);
    std::printf("\n");
  }
  for (const diagnose::Candidate& c : d.candidates)
    if (c.verdict == diagnose::Verdict::not_distinguishable)
      std::printf("  %s: not distinguishable from this data: %s. To separate it: %s.\n",
                  c.name.c_str(), c.reason.c_str(), c.needs.c_str());
  for (const diagnose::Candidate& c : d.candidates)
    if (c.verdict == diagnose::Verdict::refit_failed)
      std::printf("  %s: refit failed, not judged: %s.\n", c.name.c_str(), c.reason.c_str());
  bool any_significant = false;
  const diagnose::Candidate* const recommended = d.best();
  for (const diagnose::Candidate& c : d.candidates) {
    if (c.verdict != diagnose::Verdict::significant || &c == recommended) continue;
    any_significant = true;
    const std::string why = d.not_recommended_because(c);
    // A drift or a sensor fault is said once, above.
    if (!d.drift.found && !fault)
      std::printf("  %s: significant on the training cycles, not recommended: %s\n", c.name.c_str(),
                  why.empty() ? ("ranked after " + recommended->name).c_str() : why.c_str());
  }
  if (const diagnose::Candidate* best = recommended)
    std::printf("best: %s, %s: %s (training RMSE %.3f -> %.3f K, held-out %s -> %s K); add it with [effects] "
                "enabled = [\"%s\"] in the motor file or lptn calibrate --effect %s\n",
                best->kind == EffectKind::term ? "a term of the dictionary" : "an effect of the library",
                best->name.c_str(), best->words.c_str(), d.rmse_k, best->refit_rmse_k, kelvin(d.test_rmse_k).c_str(),
                kelvin(best->test_rmse_k_after).c_str(), best->name.c_str(), best->name.c_str());
  else if (fault)
    std::printf("Nothing is recommended: the %s sensor reads wrong (above). Calibrate around it with lptn calibrate "
                "--sensor-fault %s, then diagnose that calibration.\n", data::sensor_name(fault->sensor),
                fault->calibrate.c_str());
  else if (d.drift.found)
    std::printf("Nothing is recommended: the dump drifts (above). Calibrate on the cycles before the change, or "
                "find its cause first.\n");
  else if (any_significant) {
    std::printf("Nothing is recommended: no significant candidate has its size pinned and lowers the held-out "
                "error (above).%s\n",
                d.adequacy.adequate ? "" : " The model is not adequate: something is missing that they do not explain.");
    print_shapes(d);
  }
  else if (d.adequacy.adequate)
    std::printf("No effect of the library and no term of the dictionary improves the fit significantly "
                "(likelihood ratio at level %g, block test at %g), and the model is adequate: this data gives "
                "no reason to add one.\n", level, diagnose::Settings{}.block_level);
  else
    std::printf("No effect of the library and no term of the dictionary improves the fit significantly (likelihood "
                "ratio at level %g, block test at %g), yet the model is not adequate: something is missing that "
                "none of them explains. lptn report shows where the residual lies (cycles, operating regions, the "
                "inputs it follows).\n", level, diagnose::Settings{}.block_level);
  if (!recommended && !fault && !d.drift.found && !any_significant && !d.adequacy.adequate) print_shapes(d);
}

void run(const DiagnoseArgs& given) {
  // Under mpirun the LM refits are shared over the processes (each simulates its share of the
  // cycles); every rank holds the whole dump and does the rest too; rank 0 alone speaks and writes.
  const ProcessGroup& group = ProcessGroup::world();
  DiagnoseArgs a = given;
  if (!group.leads()) {
    a.quiet = true;
    if (std::freopen("/dev/null", "w", stdout) == nullptr) throw std::runtime_error("cannot silence rank " + std::to_string(group.rank()));
  }
  if (!a.out.empty() && !a.automatic) throw BadInput("--out: only with --auto (the calibration after forward selection)");
  // Inputs, then the outputs, before any work (a missing input is the first thing to hear of).
  for (const std::string& d : a.data) check_input_path(d, "--data");
  check_input_path(a.calibration, "--calibration", InputPath::file);
  check_output_path(a.out, a.force);
  check_output_path(a.json_out, a.force, "--json-out");
  if (!(a.level > 0 && a.level < 0.5)) throw BadInput("--level: must be in (0, 0.5), got " + std::to_string(a.level));
  const CalibrationResult calibration = load_calibration(a.calibration);
  const MotorFile motor = motor_of(calibration);
  std::vector<std::filesystem::path> paths(a.data.begin(), a.data.end());
  data::Dataset dataset = data::load_fleet_dump(paths, with_map(a.map));
  const std::vector<std::string> corrections = check::correct_as_calibrated(dataset, calibration);
  // What `lptn inspect --motor` would say of this data and the calibration's motor, repeated once.
  if (group.leads()) print_input_warnings(input_warnings(dataset, motor));
  share_work(dataset, group);
  // By name and file hash: a dump that only shares the calibration's cycle names is not its data.
  const check::Provenance provenance = check::provenance(calibration, dataset, check::motor_beside(a.data));
  const Split split = a.test_cycles.empty() ? split_of(calibration, dataset)
                                            : split_cycles(dataset, a.test_cycles, 0.0, 0);
  diagnose::Settings settings;
  settings.level = a.level;

  if (!a.json) {
    std::printf("diagnosing %s (effects: %s) on %zu training cycles, testing on %zu\n", motor.name.c_str(),
                effect_list(motor.effects).c_str(), split.train.size(), split.test.size());
    std::printf("before, as the calibration file has it (on the data it was fitted on): %s\n",
                file_figures(calibration).c_str());
    for (const std::string& c : corrections) std::printf("%s\n", c.c_str());
    if (!provenance.all_seen())
      std::printf("this is not the calibration's data: %s never seen by it. The training and test cycles below are "
                  "diagnose's own split of this data (%s), and every figure below is a refit's on it, not the "
                  "calibration's. Whether the calibration holds on this data: lptn check --data %s "
                  "--calibration %s\n",
                  provenance.summary().c_str(),
                  a.test_cycles.empty() ? "by the calibration's cycle names" : "--test-cycles",
                  joined(a.data).c_str(), a.calibration.c_str());
  }
  std::fflush(stdout);  // before the progress lines on stderr
  const auto t0 = std::chrono::steady_clock::now();
  ProgressLine line(a.quiet);
  const diagnose::Progress progress = [&](const std::string& text) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    line.update("diagnose: " + text + "  " + ProgressLine::clock(s));
  };

  if (!a.automatic) {
    const diagnose::Diagnosis d = diagnose::diagnose(motor, calibration.values(), dataset, split, settings, progress);
    line.finish();
    nlohmann::json j = diagnose::to_json(d);
    j["data"] = provenance_json(calibration, provenance, d);
    if (a.json) std::printf("%s\n", j.dump(2).c_str());
    else print_table(d, a.level);
    if (!a.json_out.empty() && group.leads()) write_file_atomically(a.json_out, j.dump(2) + "\n");
    return;
  }
  int round = 0;
  const diagnose::Selection s = diagnose::select_effects(
      motor, calibration.values(), dataset, split, settings, progress, [&](const diagnose::Diagnosis& d) {
        line.finish();
        if (a.json) return;
        std::printf("\nround %d\n", ++round);
        print_table(d, a.level);
        std::fflush(stdout);
      });
  const diagnose::Diagnosis& last = s.rounds.back();
  nlohmann::json j = diagnose::to_json(last);  // the final model's figures
  j["data"] = provenance_json(calibration, provenance, s.rounds.front());
  j["added"] = s.added;
  j["rounds"] = nlohmann::json::array();
  for (const diagnose::Diagnosis& d : s.rounds) j["rounds"].push_back(diagnose::to_json(d));
  if (!a.json_out.empty() && group.leads()) write_file_atomically(a.json_out, j.dump(2) + "\n");
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::string added;
    for (const std::string& name : s.added) added += (added.empty() ? "" : ", ") + name;
    std::printf("\nforward selection added: %s\n", added.empty() ? "nothing" : added.c_str());
  }
  if (a.out.empty()) return;
  CalibrationResult r = diagnose::updated_calibration(calibration, s.motor, last.baseline, dataset, split,
                                                      "lptn diagnose --auto from " + a.calibration);
  r.created_utc = utc_now();
  if (!group.leads()) return;
  save_calibration(r, a.out);
  if (!a.json) std::printf("%s written (effects: %s)\n", a.out.c_str(), effect_list(r.effects).c_str());
}

}  // namespace

void add_diagnose(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "diagnose", "Is the calibrated model adequate, did the motor drift between cycles, and which effect of the library or "
                  "term of the dictionary does it lack (score test, refit, block test, held-out error); under `mpirun -np N` "
                  "its LM refits are shared over N processes");
  auto a = std::make_shared<DiagnoseArgs>();
  cmd->add_option("--data", a->data, "Directories of cycle CSVs, or CSV files (the data the calibration was made from)")
      ->required()
      ->expected(1, -1);
  cmd->add_option("--calibration", a->calibration, "calibration.json (from lptn calibrate)")->required();
  add_map_option(cmd, a->map);
  cmd->add_option("--test-cycles", a->test_cycles, "Cycles held out for testing, by name (default: the calibration's split)")
      ->delimiter(',');
  cmd->add_option("--level", a->level, "False-alarm probability of the likelihood-ratio test per effect (default 0.001)");
  cmd->add_flag("--json", a->json, "Print the diagnosis as JSON: {\"rmse_k\", \"candidates\": [...]}, best first");
  cmd->add_option("--json-out", a->json_out, "Also write that JSON to this file (for lptn report --diagnosis)");
  cmd->add_flag("--auto", a->automatic, "Forward selection: add the best significant effect, refit, repeat until none is");
  cmd->add_option("--out", a->out, "With --auto: write the final calibration here");
  cmd->add_flag("--force", a->force, "Replace --out and --json-out if they exist");
  cmd->add_flag("--quiet", a->quiet, "No progress output");
  cmd->callback([a] { run(*a); });
}

}  // namespace lptn::cli
