// lptn diagnose: whether the calibrated model is adequate (adequacy.hpp), whether the motor drifted
// between cycles (drift.hpp), and which effect of the library or term of the dictionary
// (common/lptn/effects/) it lacks.
//
// For every library effect not yet in the model, and for the best-scoring few of the dictionary's
// terms (every term is scored), these questions, cheapest first:
//   score test   how strongly the residuals point along the effect's parameters at their neutral
//                value (the calibrated parameters held): one Jacobian, no fit. Ranks candidates.
//   refit        fit_lm with the effect added, from the calibrated values with the effect's
//                parameters at two starts, the score test's Gauss-Newton step and the neutral value
//                (where the effect does nothing), the better kept: the error after adding, on the
//                training cycles and on the test cycles; the likelihood-ratio statistic
//                LR = n_eff ln(RSS_before / RSS_after) against the chi-square quantile at
//                df = the parameters the effect adds. A refit that ends above the baseline from
//                every start is listed as failed, with why, and not judged.
//   blocks       the block test (internal/block_test.hpp): training cycles cut into blocks longer
//                than the residuals' correlation time, each block's gain ln(SSE before/after),
//                their mean against Student's t. Significant = LR and block test both pass.
//   held out     the test cycles' error over every sensor before and after: a candidate that
//                raises it is never recommended.
//   identifiable whether the refit can tell the effect's parameter from the ones already there
//                (correlation beyond the flag, or a standard error larger than the value).
//   pinned       recommended only where the refit pins the effect's size: a standard error at
//                most kPinnedRatio of its value (pinned()).
// n_eff is the residual count divided by the residuals' correlation time, as fit_lm corrects its
// standard errors (sensors at 1 Hz on a 10 Hz grid, slow model error: grid residuals are far from
// independent, and counting each as one would call every effect significant).
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/lm/lm.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/calibrate/calibration_result.hpp"
#include "trainer/diagnose/adequacy.hpp"
#include "trainer/diagnose/drift.hpp"
#include "trainer/diagnose/sensor_check.hpp"
#include "trainer/model/motor_effects.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::diagnose {

// --- statistics ----------------------------------------------------------------------------

// The p-quantile of the chi-square distribution with df degrees of freedom: exact for df 1 and 2,
// Wilson-Hilferty's cube-root normal approximation above (within 2 % up to p = 0.999 for df >= 3,
// and high there: a conservative threshold at diagnose's level).
double chi_square_quantile(double p, int df);
// The p-quantile (p > 0.5) of Student's t distribution with df degrees of freedom.
double student_t_quantile(double p, int df);

// --- the diagnosis -------------------------------------------------------------------------

struct Settings {
  double level = 0.001;            // false-alarm probability of the likelihood-ratio test, per effect
  // The block test's level. It is the second of three conditions (likelihood ratio, blocks, held-out
  // error) and has few blocks to work with: a 3-degree-of-freedom t quantile at 0.001 (10.2) would
  // refuse a sensor lag that cuts every block's error threefold. The false alarms of the whole
  // decision are measured on clean data over seeds (docs/diagnosis.md).
  double block_level = 0.05;
  double correlation_flag = 0.95;  // |correlation| with an existing parameter that makes an effect indistinguishable
  // A candidate's refit starts at the calibrated values; one that has not converged in this many
  // iterations is crawling along a direction the data barely supports (it is not the one to add),
  // and its verdict rests on where it got. The baseline and --auto's refits get fit_lm's default.
  int refit_iterations = 15;
  // The dictionary's terms are all scored; this many of the best-scoring are refit and tested (one
  // form per node's heat: the best-scoring).
  int term_refits = 3;
  int threads = hostio::worker_threads();
};

// refit_failed: no start of the refit ended at or below the baseline (a fit that got worse is no
// evidence either way); such a candidate is listed with why, not judged.
enum class Verdict { significant, not_distinguishable, not_significant, refit_failed };
const char* to_string(Verdict v);

// A recommendation needs the effect's size (its first parameter: a term's heat, a conductance, a
// gain; 0 is "absent") pinned: a standard error at most this share of the value, so that its
// two-sigma interval excludes the neutral value. Significance alone is not enough: a likelihood
// ratio just over its threshold on few effective residuals can carry a size of 262 +- 193 W.
inline constexpr double kPinnedRatio = 0.5;

// One start of a candidate's refit and where it ended.
struct RefitStart {
  std::string from;           // "the score test's step", "the neutral value"
  double rmse_k = 0;          // training RMSE at its end (NaN: the fit could not be made)
  int iterations = 0;
  bool converged = false;
  std::string error;          // why the fit could not be made (empty: it was)
  bool coarse_only = false;   // ended on the coarse grid, not polished: the other start ended lower there
};

struct Candidate {
  int effect = -1;
  std::string name;
  EffectKind kind = EffectKind::library;
  std::string node;                 // terms: the node it acts on ("stator_winding", ...)
  std::string formula;              // terms: its form
  std::string words;                // in physical words with the refit's values (in_words.hpp)
  int df = 0;                       // parameters the effect adds
  double score = 0;                 // score statistic (chi-square scale, correlation-corrected)
  double predicted_rmse_k = 0;      // what the score predicts the training RMSE would fall to
  double statistic = 0;             // likelihood-ratio statistic of the refit
  double threshold = 0;             // chi-square quantile it must exceed
  int blocks = 0;                   // the block test (internal/block_test.hpp): blocks compared,
  double block_gain = 0;            //   their mean ln(SSE before / SSE after),
  double block_t = 0;               //   its t statistic
  double block_threshold = 0;       //   and the quantile it must exceed
  double refit_rmse_k = 0;          // training RMSE after the refit (fit_lm's pooled residuals)
  double train_stator_rmse_k = 0;   // after the refit, stator sensor (offsets estimated per cycle)
  double test_stator_rmse_k = 0;    // after the refit; NaN without test cycles
  double test_rmse_k_after = 0;     // after the refit, every measured sensor (NaN without test cycles)
  lm::LmReport refit;                   // values, standard errors, correlated pairs (of the start kept)
  std::vector<RefitStart> starts;   // every start tried, in order; `refit` is the best that ended
  std::string start;                // the start kept
  Verdict verdict = Verdict::not_significant;
  std::string reason;               // why not distinguishable, not significant or failed (empty otherwise)
  std::string needs;                // what data would separate the effect (from the effect's notes)
};

struct Diagnosis {
  lm::LmReport baseline;                 // the calibrated model refit on the training cycles (offsets, RSS)
  Adequacy adequacy;                 // the model as it stands, against each sensor's noise
  double rmse_k = 0;                 // training RMSE before (fit_lm's pooled residuals)
  double train_stator_rmse_k = 0;    // before, stator sensor
  double test_stator_rmse_k = 0;     // before; NaN without test cycles
  double test_rmse_k = 0;            // before, every measured sensor (RMS over both, each sample once)
  double effective_residuals = 0;    // n_eff: residuals / correlation time
  std::vector<Candidate> candidates;  // the library's effects, then the dictionary's terms; each by training RMSE after the refit
  struct TermScore {
    int effect = -1;
    std::string name;
    double score = 0;
    bool feasible = false;
  };
  std::vector<TermScore> term_scores;  // every dictionary term not in the model, best score first
  Drift drift;                         // between the cycles; while one is found nothing is recommended
  // Each measured temperature sensor checked for a fault (sensor_check.hpp). A fault found outranks
  // a drift (it explains the faulty cycles better than their heat balance; the drift is then not
  // reported as found) and, while it stands, nothing is recommended.
  std::vector<SensorFinding> sensors;
  const SensorFinding* sensor_fault() const;  // the found one of smallest p, or nullptr

  // A refit that fits the training cycles better but the held-out cycles worse learned them, not
  // the physics: such a candidate is never recommended, however significant. One that leaves the
  // held-out error where it was has shown nothing there either: a recommendation needs it to fall.
  bool raises_held_out_error(const Candidate& c) const;
  // Why a significant candidate cannot be recommended, in words (empty: it can): a sensor fault or a drift found,
  // its size not pinned (pinned()), or the held-out error not falling.
  std::string not_recommended_because(const Candidate& c) const;
  // The recommendation: the first significant (and distinguishable) candidate with nothing against
  // it (not_recommended_because), or nullptr. At most one per round; none while a sensor fault or a
  // drift is found (it would absorb it).
  const Candidate* best() const;
};

// Whether the candidate's refit pins its size: a finite standard error at most kPinnedRatio of the
// value. `why` (if given) gets "P = v +- se W: ..." where it does not.
bool pinned(const Candidate& c, std::string* why = nullptr);

// Progress of long work: a line to show (stage and LM iteration).
using Progress = std::function<void(const std::string&)>;

// Diagnoses `motor` (effects and free parameters as calibrated) at `calibrated`, fitted on
// split.train and tested on split.test.
Diagnosis diagnose(const model::MotorFile& motor, const ParamVector<double>& calibrated, calibrate::DatasetRef dataset,
                   const calibrate::Split& split, const Settings& settings, const Progress& progress = {});

// Forward selection: diagnose, add the best significant and distinguishable effect (its refit
// becomes the new calibration), diagnose again, until no candidate is significant.
struct Selection {
  std::vector<Diagnosis> rounds;  // the last one found nothing to add
  std::vector<std::string> added;
  model::MotorFile motor;                // with the added effects
};
using RoundDone = std::function<void(const Diagnosis&)>;
Selection select_effects(const model::MotorFile& motor, const ParamVector<double>& calibrated, calibrate::DatasetRef dataset,
                         const calibrate::Split& split, const Settings& settings, const Progress& progress = {},
                         const RoundDone& round_done = {});

// `calibration` updated to `motor` (effects, text) and the fit `fit` (values, standard errors,
// correlated pairs) with metrics recomputed on its split; the method stays "lm". Its data record
// (files, hashes, data maps, split, time, version) is that of `dataset` and `split`, the data fitted.
calibrate::CalibrationResult updated_calibration(const calibrate::CalibrationResult& calibration,
                                                 const model::MotorFile& motor, const lm::LmReport& fit,
                                                 calibrate::DatasetRef dataset, const calibrate::Split& split,
                                                 const std::string& note);

// The diagnosis file's format (lptn diagnose --json, --json-out; docs/diagnosis.md): 2 added the
// sensor check ("sensor_faults", candidates of kind "sensor"). A reader refuses a newer one.
inline constexpr int kDiagnosisFormatVersion = 2;

// {"format_version": 2, "rmse_k": ..., "candidates": [{"effect", "statistic", "predicted_rmse_k",
// "refit_rmse_k", "significant", ...}, ...]}, best first.
nlohmann::json to_json(const Diagnosis& diagnosis);

}  // namespace lptn::diagnose
