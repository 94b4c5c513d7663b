// A diagnosis from request to result: the calibration and its motor, the data (through its map,
// with the calibration's sensor corrections), whether it is the calibration's own data, the split,
// then the diagnosis, or forward selection over it (--auto) and the calibration it ends with. The
// caller (lptn diagnose; a binding, a service) fills in the request, hears of the work through the
// events, and prints (diagnose::diagnosis_text) and saves.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/check/provenance.hpp"
#include "trainer/diagnose/diagnose.hpp"

namespace lptn::workflow {

struct DiagnosisRequest {
  std::vector<std::string> data;         // directories of cycle CSVs, or CSV files
  std::string calibration;               // calibration.json
  std::string map;                       // the data map (TOML); empty: data.toml beside the CSVs
  std::vector<std::string> test_cycles;  // held out by name; empty: the calibration's split
  double level = 0.001;                  // the likelihood-ratio test's false-alarm probability, in (0, 0.5)
  bool automatic = false;                // forward selection: add the best significant effect, refit, repeat
  bool updated_calibration = false;      // with automatic: also the calibration it ends with (scored anew)
};

// What is diagnosed, as the work begins.
struct DiagnosisPlan {
  std::string motor_name;
  EffectSet effects = 0;
  std::size_t train_cycles = 0, test_cycles = 0;
  std::string calibration_figures;       // the file's own figures: "train stator 0.346 K, rotor 0.415 K; test ..."
  std::vector<std::string> corrections;  // the calibration's sensor faults taken out of the readings, one line each
  check::Provenance provenance;          // whether this is the calibration's data
  // Where it is not: what that means for every figure that follows, and how to ask instead whether
  // the calibration holds on it (lptn check). Empty for the calibration's own data.
  std::string not_its_data;
};

struct DiagnosisEvents {
  // What `lptn inspect --motor` would say of this data and the calibration's motor, once.
  std::function<void(const std::vector<std::string>& warnings)> input_warnings;
  std::function<void(const DiagnosisPlan& plan)> started;
  diagnose::Progress progress;     // the stage at work
  diagnose::RoundDone round_done;  // --auto: each round's diagnosis as it ends
};

struct DiagnosisOutcome {
  std::vector<diagnose::Diagnosis> rounds;  // one without --auto; with it, the last found nothing to add
  std::vector<std::string> added;           // --auto: the effects forward selection added, in order
  // The diagnosis as `--json` prints it: the last round's, with "data" (the calibration's figures,
  // whether this is its data, the refit) and with --auto "added" and every round.
  nlohmann::json json;
  // --auto with updated_calibration: the calibration after forward selection (the motor with what it
  // added, refitted and scored).
  std::optional<calibrate::CalibrationResult> updated;
  const diagnose::Diagnosis& last() const { return rounds.back(); }
};

// BadInput naming the option or file for input that cannot be diagnosed. Under an MPI job every
// process calls it (the LM refits are shared); each returns the same outcome.
DiagnosisOutcome diagnose(const DiagnosisRequest& request, const DiagnosisEvents& events = {});

}  // namespace lptn::workflow
