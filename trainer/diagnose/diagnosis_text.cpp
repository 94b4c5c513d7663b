#include "trainer/diagnose/diagnosis_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "trainer/data/sensor_fault.hpp"
#include "trainer/diagnose/in_words.hpp"

namespace lptn::diagnose {

std::string effect_list(EffectSet effects) {
  std::string out;
  for (int e = 0; e < kNumEffects; ++e)
    if (effects & effect_bit(e)) out += (out.empty() ? "" : ", ") + std::string(EffectLibrary::kNames[e]);
  return out.empty() ? "none" : out;
}

std::string kelvin(double v) {
  if (!std::isfinite(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", v);
  return buf;
}

namespace {

// printf into a string.
struct Text {
  std::string text;
  [[gnu::format(printf, 2, 3)]] void add(const char* format, ...) {
    va_list args;
    va_start(args, format);
    char buf[2048];
    const int n = std::vsnprintf(buf, sizeof buf, format, args);
    va_end(args);
    if (n < 0) return;
    if (static_cast<std::size_t>(n) < sizeof buf) {
      text += buf;
      return;
    }
    std::string big(static_cast<std::size_t>(n) + 1, '\0');
    va_start(args, format);
    std::vsnprintf(big.data(), big.size(), format, args);
    va_end(args);
    big.resize(static_cast<std::size_t>(n));
    text += big;
  }
};

// "0.981..1.012": the spread of the per-cycle factors.
std::string factor_range(const Drift& drift) {
  if (drift.factors.empty()) return "-";
  double lo = drift.factors.front().factor, hi = lo;
  for (const CycleFactor& f : drift.factors) lo = std::min(lo, f.factor), hi = std::max(hi, f.factor);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3f..%.3f", lo, hi);
  return buf;
}

// Where nothing explains the residual: what its shape suggests, per sensor that is not adequate.
void add_shapes(Text& out, const Diagnosis& d) {
  for (const SensorAdequacy& s : d.adequacy.sensors)
    if (const std::string words = shape_in_words(s); !words.empty())
      out.add("  what the shape suggests: %s.\n", words.c_str());
}

}  // namespace

std::string diagnosis_text(const Diagnosis& d, double level) {
  Text out;
  out.add("the baseline refit from the calibration's values (%d LM iterations) on the training cycles: "
          "training RMSE %.3f K (stator %s K), test stator %s K; %.0f effective residuals (correlation time %.1f steps)\n",
          d.baseline.iterations, d.rmse_k, kelvin(d.train_stator_rmse_k).c_str(), kelvin(d.test_stator_rmse_k).c_str(),
          d.effective_residuals, d.baseline.correlation_time);
  out.add("the model against its sensors' noise (adequate within %.1fx):\n", kAdequateRatio);
  for (const SensorAdequacy& s : d.adequacy.sensors) out.add("  %s\n", describe(s).c_str());
  const SensorFinding* const fault = d.sensor_fault();
  for (const SensorFinding& s : d.sensors)
    if (s.found)
      out.add("SENSOR FAULT: %s.\n  Inspect %s. Nothing is recommended while a sensor reads wrong: an effect "
              "would absorb the fault.\n", s.finding.c_str(), s.inspect.c_str());
    else
      out.add("no %s sensor fault: %s\n", data::sensor_name(s.sensor), s.finding.c_str());
  if (d.drift.found)
    out.add("drift between cycles: %s.\n  Inspect %s. Nothing is recommended while the dump drifts: an effect "
            "would absorb the change.\n", d.drift.finding.c_str(), d.drift.inspect.c_str());
  else if (fault && !d.drift.finding.empty())
    out.add("no drift of the motor between cycles: %s\n", d.drift.finding.c_str());
  else
    out.add("no drift between cycles (per-cycle %s factors %s, p = %.2f)\n", to_string(d.drift.group),
            factor_range(d.drift).c_str(), d.drift.p_value);
  if (d.candidates.empty()) {
    out.add("every effect of the library and term of the dictionary is already in the model%s\n",
            d.adequacy.adequate ? "" : ", and something is still missing: it is none of them");
    if (!fault && !d.drift.found) add_shapes(out, d);
    return out.text;
  }
  out.add("%-34s %10s %9s %21s %21s %21s  %s\n", "effect or term", "score", "pred. K", "LR / threshold",
          "train K before->after", "held-out K bef.->aft.", "verdict");
  for (const Candidate& c : d.candidates) {
    char lr[32], train[40], test[40];
    std::snprintf(lr, sizeof lr, "%.1f / %.1f", c.statistic, c.threshold);
    std::snprintf(train, sizeof train, "%.3f -> %.3f", d.rmse_k, c.refit_rmse_k);
    // Held out: both sensors (a candidate that helps one sensor and hurts the other shows here).
    std::snprintf(test, sizeof test, "%s -> %s", kelvin(d.test_rmse_k).c_str(), kelvin(c.test_rmse_k_after).c_str());
    out.add("%-34s %10.1f %9.3f %21s %21s %21s  %s\n", c.name.c_str(), c.score, c.predicted_rmse_k, lr, train, test,
            to_string(c.verdict));
  }
  for (const Candidate& c : d.candidates)
    if (c.kind == EffectKind::term) out.add("  %s: %s\n", c.name.c_str(), c.words.c_str());
  if (!d.term_scores.empty()) {
    out.add("  dictionary: %zu terms scored; best scores", d.term_scores.size());
    for (std::size_t i = 0; i < d.term_scores.size() && i < 5; ++i)
      out.add("%s %s %.1f", i ? "," : "", d.term_scores[i].name.c_str(), d.term_scores[i].score);
    out.add("\n");
  }
  for (const Candidate& c : d.candidates)
    if (c.verdict == Verdict::not_distinguishable)
      out.add("  %s: not distinguishable from this data: %s. To separate it: %s.\n",
              c.name.c_str(), c.reason.c_str(), c.needs.c_str());
  for (const Candidate& c : d.candidates)
    if (c.verdict == Verdict::refit_failed)
      out.add("  %s: refit failed, not judged: %s.\n", c.name.c_str(), c.reason.c_str());
  bool any_significant = false;
  const Candidate* const recommended = d.best();
  for (const Candidate& c : d.candidates) {
    if (c.verdict != Verdict::significant || &c == recommended) continue;
    any_significant = true;
    const std::string why = d.not_recommended_because(c);
    // A drift or a sensor fault is said once, above.
    if (!d.drift.found && !fault)
      out.add("  %s: significant on the training cycles, not recommended: %s\n", c.name.c_str(),
              why.empty() ? ("ranked after " + recommended->name).c_str() : why.c_str());
  }
  if (const Candidate* best = recommended)
    out.add("best: %s, %s: %s (training RMSE %.3f -> %.3f K, held-out %s -> %s K); add it with [effects] "
            "enabled = [\"%s\"] in the motor file or lptn calibrate --effect %s\n",
            best->kind == EffectKind::term ? "a term of the dictionary" : "an effect of the library",
            best->name.c_str(), best->words.c_str(), d.rmse_k, best->refit_rmse_k, kelvin(d.test_rmse_k).c_str(),
            kelvin(best->test_rmse_k_after).c_str(), best->name.c_str(), best->name.c_str());
  else if (fault)
    out.add("Nothing is recommended: the %s sensor reads wrong (above). Calibrate around it with lptn calibrate "
            "--sensor-fault %s, then diagnose that calibration.\n", data::sensor_name(fault->sensor),
            fault->calibrate.c_str());
  else if (d.drift.found)
    out.add("Nothing is recommended: the dump drifts (above). Calibrate on the cycles before the change, or "
            "find its cause first.\n");
  else if (any_significant) {
    out.add("Nothing is recommended: no significant candidate has its size pinned and lowers the held-out "
            "error (above).%s\n",
            d.adequacy.adequate ? "" : " The model is not adequate: something is missing that they do not explain.");
    add_shapes(out, d);
  }
  else if (d.adequacy.adequate)
    out.add("No effect of the library and no term of the dictionary improves the fit significantly "
            "(likelihood ratio at level %g, block test at %g), and the model is adequate: this data gives "
            "no reason to add one.\n", level, Settings{}.block_level);
  else
    out.add("No effect of the library and no term of the dictionary improves the fit significantly (likelihood "
            "ratio at level %g, block test at %g), yet the model is not adequate: something is missing that "
            "none of them explains. lptn report shows where the residual lies (cycles, operating regions, the "
            "inputs it follows).\n", level, Settings{}.block_level);
  if (!recommended && !fault && !d.drift.found && !any_significant && !d.adequacy.adequate) add_shapes(out, d);
  return out.text;
}

}  // namespace lptn::diagnose
