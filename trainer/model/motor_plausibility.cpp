#include "trainer/model/motor_plausibility.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string_view>
#include <type_traits>
#include <toml++/toml.h>

#include "trainer/data/inspection.hpp"

namespace lptn::model {
namespace {

// Two significant digits, without an exponent between 0.001 and 100000 ("0.0078", "1.2", "4650").
std::string num2(double v) {
  char buf[48];
  const double a = std::fabs(v);
  if (a == 0) return "0";
  if (a >= 1e-3 && a < 1e5) {
    const int digits = std::max(0, 1 - static_cast<int>(std::floor(std::log10(a))));
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  } else {
    std::snprintf(buf, sizeof buf, "%.2g", v);
  }
  return buf;
}

// A value as the user wrote it, near enough ("80", "0.393", "6e+04").
std::string num(double v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// A power, energy rate or capacity with its prefix: "3.2 MW", "310 kW", "60 J/K".
std::string si(double v, std::string_view unit) {
  static constexpr struct {
    double scale;
    const char* prefix;
  } kPrefixes[] = {{1e9, "G"}, {1e6, "M"}, {1e3, "k"}};
  for (const auto& p : kPrefixes) {
    if (std::fabs(v) >= p.scale) return num2(v / p.scale) + " " + p.prefix + std::string(unit);
  }
  return num2(v) + " " + std::string(unit);
}

struct Range {
  double lo, hi;
  // Ahead of every other finding: the value the others are scaled by (rated power).
  bool root_cause = false;

  bool holds(double v) const { return v >= lo && v <= hi; }
  // In decades of the value over the range's nearest end, so that findings of different kinds
  // compare (a capacitance 1000x too small before an exponent 20 % too large).
  double how_far(double v) const {
    if (holds(v)) return 0;
    const double decades = v <= 0 ? 10 : v < lo ? std::log10(lo / v) : std::log10(v / hi);
    return root_cause ? 1000 + decades : decades;
  }
};

class Checker {
 public:
  explicit Checker(const MotorFile& motor) {
    if (motor.text.empty()) return;
    try {
      root_ = toml::parse(motor.text, motor.path.string());
      parsed_ = true;
    } catch (const toml::parse_error&) {
      parsed_ = false;  // a file already read once; lines are a courtesy
    }
  }

  // `value` at `key` against `range`; `message` says what the value means, `plausible` the range in
  // the motor file's units (and, after it, where the range comes from).
  void check(const std::string& key, double value, const Range& range, const std::string& message,
             const std::string& plausible) {
    if (range.holds(value)) return;
    findings_.push_back({key, value, message, plausible, line_of(key), range.how_far(value)});
  }

  bool has(const std::string& key) const { return parsed_ && root_.at_path(key).node() != nullptr; }

  std::vector<MotorFinding> take() {
    std::stable_sort(findings_.begin(), findings_.end(),
                     [](const MotorFinding& a, const MotorFinding& b) { return a.how_far > b.how_far; });
    return std::move(findings_);
  }

 private:
  int line_of(const std::string& key) const {
    if (!parsed_) return 0;
    const toml::node* node = root_.at_path(key).node();
    return node ? static_cast<int>(node->source().begin.line) : 0;
  }

  toml::table root_;
  bool parsed_ = false;
  std::vector<MotorFinding> findings_;
};

// "electrical.stator_resistance_20c_ohm" -> "stator_resistance_20c_ohm"
std::string leaf(const std::string& key) { return key.substr(key.rfind('.') + 1); }

std::string said(const std::string& key, double value) { return leaf(key) + " = " + num(value); }

void check_nameplate(Checker& c, const MotorConstants<double>& m) {
  const double apparent = std::sqrt(3.0) * m.rated_voltage_v * m.rated_current_a;
  const double p = m.rated_power_w;
  c.check("nameplate.rated_power_w", p, {0.4 * apparent, apparent, true},
          said("rated_power_w", p) + " is " + num2(100 * p / apparent) + " % of sqrt(3) x rated voltage x rated current (" +
              si(apparent, "VA") + "; the ranges that scale with rated power follow it)",
          si(0.4 * apparent, "W") + ".." + si(apparent, "W") + " (efficiency times power factor 0.4..1)");
}

void check_electrical(Checker& c, const MotorConstants<double>& m) {
  const double p = m.rated_power_w, i = m.rated_current_a;
  const auto resistance = [&](const std::string& key, double r, double current, const char* what) {
    const double per_ohm = 3 * current * current;  // W of copper loss per ohm at that current
    if (!(per_ohm > 0)) return;
    const Range range{0.001 * p / per_ohm, 0.15 * p / per_ohm};
    c.check(key, r, range,
            said(key, r) + " gives " + si(r * per_ohm, "W") + " of " + what + " at rated current (rated power " +
                si(p, "W") + ")",
            num2(range.lo) + ".." + num2(range.hi) + " ohm (a copper loss of 0.1..15 % of rated power)");
  };
  resistance("electrical.stator_resistance_20c_ohm", m.stator_resistance_20c_ohm, i, "copper loss");
  const double rotor_current = std::sqrt(std::max(0.0, i * i - m.magnetizing_current_a * m.magnetizing_current_a));
  resistance("electrical.rotor_resistance_20c_ohm", m.rotor_resistance_20c_ohm, rotor_current, "rotor copper loss");

  const auto alpha = [&](const std::string& key, double a, const Range& range, const std::string& plausible) {
    std::string message = said(key, a) + " per K: copper's is 0.00393, aluminium's 0.00403";
    if (range.holds(a / 100)) message += "; " + num(a) + " looks like a percent per kelvin typed as a fraction (" +
                                         num(a) + " %/K = " + num(a / 100) + "/K)";
    else if (range.holds(a * 100)) message += "; " + num(a) + " looks like a fraction divided by 100 once too often";
    c.check(key, a, range, message, plausible);
  };
  alpha("electrical.stator_resistance_alpha_per_k", m.stator_resistance_alpha_per_k, {0.003, 0.0045},
        "0.003..0.0045 per K (copper, aluminium)");
  alpha("electrical.rotor_resistance_alpha_per_k", m.rotor_resistance_alpha_per_k, {0.001, 0.0045},
        "0.001..0.0045 per K (cages of copper, aluminium, brass or bronze)");

  const Range im{0.1 * i, 0.7 * i};
  c.check("electrical.magnetizing_current_a", m.magnetizing_current_a, im,
          said("magnetizing_current_a", m.magnetizing_current_a) + " A is " +
              num2(100 * m.magnetizing_current_a / i) + " % of rated current (" + num(i) + " A)",
          num2(im.lo) + ".." + num2(im.hi) + " A (10..70 % of rated current; 20..50 % usual)");
}

void check_losses(Checker& c, const MotorFile& motor) {
  const MotorConstants<double>& m = motor.constants;
  const double p = m.rated_power_w;
  const auto share = [&](const std::string& key, double w, double most, const char* usual) {
    c.check(key, w, {0, most * p},
            said(key, w) + " W is " + num2(100 * w / p) + " % of rated power (" + si(p, "W") + ")",
            "0.." + si(most * p, "W") + " (0.." + num(100 * most) + " % of rated power; " + usual + ")");
  };
  share("losses.stray_rated_w", m.stray_rated_w, 0.05, "0.5..2.5 % usual");
  share("losses.iron_rated_w", m.iron_rated_w, 0.10, "1..3 % usual");
  double harmonic_peak = 0;
  for (int k = 0; k < m.harmonic_points; ++k) harmonic_peak = std::max(harmonic_peak, m.harmonic_loss_w[k]);
  c.check("losses.harmonic_loss_w", harmonic_peak, {0, 0.1 * p},
          "harmonic_loss_w reaches " + si(harmonic_peak, "W") + ", " + num2(100 * harmonic_peak / p) +
              " % of rated power (" + si(p, "W") + ")",
          "0.." + si(0.1 * p, "W") + " at every point (0..10 % of rated power)");
  c.check("losses.iron_alpha", m.iron_alpha, {1.0, 2.0},
          said("iron_alpha", m.iron_alpha) + ": the iron loss's frequency exponent",
          "1..2 (hysteresis grows with f, eddy currents with f^2)");
  c.check("losses.iron_beta", m.iron_beta, {1.5, 3.0},
          said("iron_beta", m.iron_beta) + ": the iron loss's flux-density exponent",
          "1.5..3 (Steinmetz; eddy currents grow with B^2)");
  // The shares k_stray, k_harm, k_pfe are held to [0, 1] by the loader already.
  for (const int k : {kKStemp, kKRtemp}) {
    const std::string name(param_spec(k).name);
    const std::string key = c.has("parameters." + name) ? "parameters." + name + ".initial" : "losses." + name;
    const double v = motor.parameters[k].initial;
    c.check(key, v, {0.5, 2.0},
            said(name, v) + ": a factor on the " +
                (k == kKStemp ? "stator" : "rotor") + " copper loss",
            "0.5..2 (a correction of the copper loss, not another loss)");
  }
}

void check_thermal(Checker& c, const MotorConstants<double>& m) {
  const double p = m.rated_power_w;
  for_each_motor_constant(
      [&](const MotorField& f, const auto& member) {
        if constexpr (std::is_array_v<std::remove_cvref_t<decltype(member)>>) {
          if (f.shape != FieldShape::per_node || f.name != "capacitance_j_per_k") return;
          for (int n = 0; n < kNumNodes; ++n) {
            const std::string key = "thermal." + std::string(f.node_keys[n]);
            const double cap = member[n];
            const Range range{0.005 * p, 10 * p};
            c.check(key, cap, range,
                    said(key, cap) + " J/K for the " + std::string(f.node_names[n]) + " is " + num2(cap / p) +
                        " J/K per watt of rated power (" + si(p, "W") + ")",
                    si(range.lo, "J/K") + ".." + si(range.hi, "J/K") + " (0.005..10 J/K per watt of rated power)");
          }
        }
      },
      m);
  const Range airflow{1.7e-7 * p, 6.3e-5 * p};
  c.check("thermal.nominal_airflow_m3s", m.nominal_airflow_m3s, airflow,
          said("nominal_airflow_m3s", m.nominal_airflow_m3s) + " m^3/s for a rated power of " + si(p, "W"),
          num2(airflow.lo) + ".." + num2(airflow.hi) +
              " m^3/s (losses of 1..15 % of rated power carried off with the air warming 2..50 K)");
  c.check("thermal.airflow_exponent", m.airflow_exponent, {0.3, 1.0},
          said("airflow_exponent", m.airflow_exponent) + ": how the conductances to air follow the airflow",
          "0.3..1 (forced convection: 0.5 laminar .. 0.8 turbulent)");
  c.check("thermal.min_airflow_fraction", m.min_airflow_fraction, {0.0, 0.5},
          said("min_airflow_fraction", m.min_airflow_fraction) + ": the cooling left when the blower stops",
          "0..0.5 (natural convection keeps a tenth or so)");
}

void check_parameters(Checker& c, const MotorFile& motor) {
  const double kw = motor.constants.rated_power_w / 1000;
  const auto conductance = [&](int k, double most_per_kw, const char* where) {
    const ParameterSetting& s = motor.parameters[k];
    if (!s.in_file) return;
    const std::string name(param_spec(k).name);
    const Range range{0.001 * kw, most_per_kw * kw};
    const std::string plausible = num2(range.lo) + ".." + num2(range.hi) + " W/K (0.001.." + num2(most_per_kw) +
                                  " W/K per kW of rated power, " + where + ")";
    c.check("parameters." + name + ".initial", s.initial, range,
            name + ".initial = " + num(s.initial) + " W/K for a rated power of " + si(1000 * kw, "W"), plausible);
    // Bounds wider than the plausible range are harmless; bounds that leave it entirely are not.
    if (s.max < range.lo)
      c.check("parameters." + name + ".max", s.max, range,
              name + ".max = " + num(s.max) + " W/K: the fit can only reach implausibly small values", plausible);
    if (s.min > range.hi)
      c.check("parameters." + name + ".min", s.min, range,
              name + ".min = " + num(s.min) + " W/K: the fit can only reach implausibly large values", plausible);
  };
  for (const int k : kConductancesToAir) conductance(k, 15, "to the cooling air");
  for (const int k : {kLambda12s, kLambda12r}) conductance(k, 50, "within the stator or the rotor");
  if (const int k = param_index("airgap_lambda"); k >= 0) conductance(k, 50, "across the air gap");
  if (const int k = param_index("windage_base_w"); k >= 0 && motor.parameters[k].in_file) {
    const double p = motor.constants.rated_power_w;
    const double w = motor.parameters[k].initial;
    c.check("parameters.windage_base_w.initial", w, {0, 0.05 * p},
            "windage_base_w.initial = " + num(w) + " W is " + num2(100 * w / p) + " % of rated power (" + si(p, "W") + ")",
            "0.." + si(0.05 * p, "W") + " (0..5 % of rated power)");
  }
}

}  // namespace

std::vector<MotorFinding> check_motor_plausibility(const MotorFile& motor) {
  Checker c(motor);
  check_nameplate(c, motor.constants);
  check_electrical(c, motor.constants);
  check_losses(c, motor);
  check_thermal(c, motor.constants);
  check_parameters(c, motor);
  return c.take();
}

std::string format_motor_finding(const MotorFile& motor, const MotorFinding& f) {
  std::string out = motor.path.string();
  if (f.line > 0) out += ":" + std::to_string(f.line);
  return out + ": key '" + f.key + "': " + f.message + "; plausible " + f.plausible;
}

std::vector<std::string> motor_warnings(const MotorFile& motor) {
  std::vector<std::string> out;
  for (const MotorFinding& f : check_motor_plausibility(motor)) out.push_back(format_motor_finding(motor, f));
  return out;
}

std::string implausible_values_summary(const MotorFile& motor) {
  const std::vector<MotorFinding> findings = check_motor_plausibility(motor);
  if (findings.empty()) return {};
  std::string out = format_motor_finding(motor, findings.front());
  if (findings.size() > 1) {
    out += " (and " + std::to_string(findings.size() - 1) + " more implausible:";
    for (std::size_t i = 1; i < findings.size(); ++i) out += (i == 1 ? " " : ", ") + findings[i].key;
    out += ")";
  }
  return out;
}

std::vector<std::string> input_warnings(const data::Dataset& dataset, const MotorFile& motor) {
  std::vector<std::string> out = data::inspection_warnings(dataset, motor.constants);
  for (std::string& w : motor_warnings(motor)) out.push_back(std::move(w));
  return out;
}

}  // namespace lptn::model
