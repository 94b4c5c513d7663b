#include "trainer/model/motor_file.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <string_view>
#include <toml++/toml.h>

namespace lptn {
namespace {

// The error is one line (motor_file.hpp), but toml++'s descriptions quote the character they
// stopped at, a newline too, and a quoted key may hold one.
std::string one_line(std::string message) {
  std::replace_if(message.begin(), message.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  return message;
}

[[noreturn]] void fail(const std::filesystem::path& file, const toml::source_region& where, std::string_view key,
                       std::string_view reason) {
  std::ostringstream s;
  s << file.string() << ':' << where.begin.line << ": key '" << key << "': " << reason;
  throw MotorFileError(one_line(s.str()));
}

// Reads a table's keys, refusing any it does not know and naming any required key that is missing.
class TableReader {
 public:
  TableReader(const toml::table& table, std::string prefix, const std::filesystem::path& file)
      : table_(table), prefix_(std::move(prefix)), file_(file) {}

  double number(std::string_view key, bool required = true, double fallback = 0.0) {
    seen_.insert(std::string(key));
    const toml::node* node = table_.get(key);
    if (!node) {
      if (required) fail(file_, table_.source(), full(key), "missing (required)");
      return fallback;
    }
    const auto value = node->value<double>();
    if (!value || !std::isfinite(*value)) fail(file_, node->source(), full(key), "must be a finite number");
    return *value;
  }

  double positive(std::string_view key, bool required = true, double fallback = 0.0) {
    const double v = number(key, required, fallback);
    if (!(v > 0)) fail(file_, where(key), full(key), "must be greater than zero");
    return v;
  }

  double fraction(std::string_view key) {
    const double v = number(key);
    if (v < 0 || v > 1) fail(file_, where(key), full(key), "must lie between 0 and 1");
    return v;
  }

  bool boolean(std::string_view key, bool fallback) {
    seen_.insert(std::string(key));
    const toml::node* node = table_.get(key);
    if (!node) return fallback;
    const auto value = node->value<bool>();
    if (!value) fail(file_, node->source(), full(key), "must be true or false");
    return *value;
  }

  std::vector<double> numbers(std::string_view key) {
    seen_.insert(std::string(key));
    const toml::node* node = table_.get(key);
    if (!node) fail(file_, table_.source(), full(key), "missing (required)");
    const toml::array* array = node->as_array();
    if (!array) fail(file_, node->source(), full(key), "must be an array of numbers");
    std::vector<double> out;
    for (const toml::node& item : *array) {
      const auto v = item.value<double>();
      if (!v || !std::isfinite(*v)) fail(file_, item.source(), full(key), "must hold finite numbers only");
      out.push_back(*v);
    }
    return out;
  }

  const toml::table& sub_table(std::string_view key) {
    seen_.insert(std::string(key));
    const toml::node* node = table_.get(key);
    if (!node) fail(file_, table_.source(), full(key), "missing table (required)");
    const toml::table* t = node->as_table();
    if (!t) fail(file_, node->source(), full(key), "must be a table");
    return *t;
  }

  const toml::table* optional_table(std::string_view key) {
    seen_.insert(std::string(key));
    const toml::node* node = table_.get(key);
    if (!node) return nullptr;
    if (!node->as_table()) fail(file_, node->source(), full(key), "must be a table");
    return node->as_table();
  }

  void allow(std::string_view key) { seen_.insert(std::string(key)); }

  void refuse_unknown() const {
    for (const auto& [key, node] : table_) {
      if (!seen_.count(std::string(key.str()))) fail(file_, node.source(), full(key.str()), "unknown key");
    }
  }

  toml::source_region where(std::string_view key) const {
    const toml::node* node = table_.get(key);
    return node ? node->source() : table_.source();
  }
  std::string full(std::string_view key) const { return prefix_.empty() ? std::string(key) : prefix_ + "." + std::string(key); }

 private:
  const toml::table& table_;
  std::string prefix_;
  const std::filesystem::path& file_;
  std::set<std::string> seen_;
};

}  // namespace

std::array<ParameterSetting, kNumParams> default_parameter_settings() {
  std::array<ParameterSetting, kNumParams> out{};
  for (int i = 0; i < kNumParams; ++i) {
    const ParamSpec& s = param_spec(i);
    out[i] = {s.initial, s.min, s.max, true, false};
  }
  // The loss-split factors are fixed unless the user asks to calibrate them (the paper calibrates
  // the conductances).
  for (int i = kKStemp; i <= kKPfe; ++i) out[i].calibrate = false;
  return out;
}

ParamVector<double> MotorFile::initial_values() const {
  ParamVector<double> p{};
  for (int i = 0; i < kNumParams; ++i) p[i] = parameters[i].initial;
  return p;
}

MotorFile parse_motor_file(const std::string& text, const std::filesystem::path& shown_as) {
  toml::table root;
  try {
    root = toml::parse(text, shown_as.string());
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << shown_as.string() << ':' << e.source().begin.line << ": " << e.description();
    throw MotorFileError(one_line(s.str()));
  }
  MotorFile motor;
  motor.path = shown_as;
  motor.text = text;
  motor.parameters = default_parameter_settings();
  TableReader top(root, "", shown_as);
  if (const toml::node* n = root.get("name")) {
    top.allow("name");
    if (!n->is_string()) fail(shown_as, n->source(), "name", "must be a string");
    motor.name = n->value<std::string>().value_or("");
  }
  MotorConstants<double>& c = motor.constants;

  {
    TableReader t(top.sub_table("nameplate"), "nameplate", shown_as);
    const double pp = t.positive("pole_pairs");
    if (pp != std::floor(pp) || pp > 16) fail(shown_as, t.where("pole_pairs"), "nameplate.pole_pairs", "must be a whole number from 1 to 16");
    c.pole_pairs = static_cast<int>(pp);
    c.rated_frequency_hz = t.positive("rated_frequency_hz");
    c.rated_voltage_v = t.positive("rated_voltage_v");
    c.rated_current_a = t.positive("rated_current_a");
    c.rated_power_w = t.positive("rated_power_w");
    t.refuse_unknown();
  }
  {
    TableReader t(top.sub_table("electrical"), "electrical", shown_as);
    c.stator_resistance_20c_ohm = t.positive("stator_resistance_20c_ohm");
    c.stator_resistance_alpha_per_k = t.number("stator_resistance_alpha_per_k");
    c.rotor_resistance_20c_ohm = t.positive("rotor_resistance_20c_ohm");
    c.rotor_resistance_alpha_per_k = t.number("rotor_resistance_alpha_per_k");
    c.magnetizing_current_a = t.positive("magnetizing_current_a");
    if (c.magnetizing_current_a >= c.rated_current_a)
      fail(shown_as, t.where("magnetizing_current_a"), "electrical.magnetizing_current_a", "must be below nameplate.rated_current_a");
    t.refuse_unknown();
  }
  const toml::table& losses = top.sub_table("losses");
  {
    TableReader t(losses, "losses", shown_as);
    c.stray_rated_w = t.number("stray_rated_w");
    c.iron_rated_w = t.number("iron_rated_w");
    if (c.stray_rated_w < 0) fail(shown_as, t.where("stray_rated_w"), "losses.stray_rated_w", "must not be negative");
    if (c.iron_rated_w < 0) fail(shown_as, t.where("iron_rated_w"), "losses.iron_rated_w", "must not be negative");
    c.iron_alpha = t.positive("iron_alpha");
    c.iron_beta = t.positive("iron_beta");
    const auto f = t.numbers("harmonic_frequency_hz");
    const auto p = t.numbers("harmonic_loss_w");
    if (f.size() != p.size())
      fail(shown_as, t.where("harmonic_loss_w"), "losses.harmonic_loss_w", "must have as many entries as losses.harmonic_frequency_hz");
    if (f.empty() || f.size() > static_cast<std::size_t>(kMaxHarmonicPoints))
      fail(shown_as, t.where("harmonic_frequency_hz"), "losses.harmonic_frequency_hz",
           "must have 1 to " + std::to_string(kMaxHarmonicPoints) + " entries");
    for (std::size_t i = 0; i < f.size(); ++i) {
      if (i > 0 && !(f[i] > f[i - 1]))
        fail(shown_as, t.where("harmonic_frequency_hz"), "losses.harmonic_frequency_hz", "must increase strictly");
      if (p[i] < 0) fail(shown_as, t.where("harmonic_loss_w"), "losses.harmonic_loss_w", "must not be negative");
      c.harmonic_frequency_hz[i] = f[i];
      c.harmonic_loss_w[i] = p[i];
    }
    c.harmonic_points = static_cast<int>(f.size());
    // The loss-split factors live here unless [parameters.NAME] takes them over for calibration.
    const toml::table* params = root.get_as<toml::table>("parameters");
    for (int i = kKStemp; i <= kKPfe; ++i) {
      const std::string_view key = param_spec(i).name;
      const bool calibrated_instead = params && params->get(key);
      if (calibrated_instead) {
        if (losses.get(key))
          fail(shown_as, t.where(key), "losses." + std::string(key),
               "given both here and as [parameters." + std::string(key) + "]; keep one");
        continue;
      }
      const double v = i <= kKRtemp ? t.positive(key) : t.fraction(key);
      const ParamSpec& spec = param_spec(i);
      motor.parameters[i] = {v, std::min(spec.min, v), std::max(spec.max, v), false, true};
    }
    t.refuse_unknown();
  }
  {
    TableReader t(top.sub_table("thermal"), "thermal", shown_as);
    c.capacitance_j_per_k[0] = t.positive("capacitance_stator_winding_j_per_k");
    c.capacitance_j_per_k[1] = t.positive("capacitance_stator_core_j_per_k");
    c.capacitance_j_per_k[2] = t.positive("capacitance_rotor_winding_j_per_k");
    c.capacitance_j_per_k[3] = t.positive("capacitance_rotor_core_j_per_k");
    c.nominal_airflow_m3s = t.positive("nominal_airflow_m3s");
    c.airflow_exponent = t.positive("airflow_exponent");
    c.min_airflow_fraction = t.positive("min_airflow_fraction", false, c.min_airflow_fraction);
    t.refuse_unknown();
  }
  if (const toml::table* params = top.optional_table("parameters")) {
    for (const auto& [key, node] : *params) {
      const std::string name(key.str());
      const int index = param_index(name);
      if (index < 0) fail(shown_as, node.source(), "parameters." + name, "unknown parameter");
      const toml::table* pt = node.as_table();
      if (!pt) fail(shown_as, node.source(), "parameters." + name, "must be a table with initial, min, max");
      TableReader t(*pt, "parameters." + name, shown_as);
      ParameterSetting& s = motor.parameters[index];
      s.min = t.number("min", false, s.min);
      s.max = t.number("max", false, s.max);
      s.initial = t.number("initial");
      s.calibrate = t.boolean("calibrate", true);
      s.in_file = true;
      t.refuse_unknown();
      if (!(s.min < s.max)) fail(shown_as, t.where("max"), "parameters." + name + ".max", "must be greater than min (bounds swapped?)");
      if (s.initial < s.min || s.initial > s.max)
        fail(shown_as, t.where("initial"), "parameters." + name + ".initial", "must lie within [min, max]");
      const ParamSpec& spec = param_spec(index);
      if (spec.min > 0 && s.min <= 0)
        fail(shown_as, t.where("min"), "parameters." + name + ".min", "must be greater than zero (" + std::string(spec.unit) + ", log scale)");
      if (index >= kKStray && index <= kKPfe && (s.min < 0 || s.max > 1))
        fail(shown_as, t.where("max"), "parameters." + name, "a share must stay within [0, 1]");
    }
  }
  if (const toml::table* effects = top.optional_table("effects")) {
    TableReader t(*effects, "effects", shown_as);
    t.allow("enabled");
    if (const toml::node* n = effects->get("enabled")) {
      const toml::array* list = n->as_array();
      if (!list) fail(shown_as, n->source(), "effects.enabled", "must be an array of effect names");
      for (const toml::node& item : *list) {
        const auto name = item.value<std::string>();
        const int e = name ? effect_index(*name) : -1;
        if (e < 0) {
          std::string known;
          for (auto k : EffectLibrary::kNames) known += (known.empty() ? "" : ", ") + std::string(k);
          fail(shown_as, item.source(), "effects.enabled", "unknown effect '" + name.value_or("?") + "' (known: " + known + ")");
        }
        motor.effects |= effect_bit(e);
      }
    }
    t.refuse_unknown();
  }
  top.refuse_unknown();
  return motor;
}

MotorFile load_motor_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MotorFileError(path.string() + ": cannot open the motor file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_motor_file(text.str(), path);
}

namespace {
// The shortest text that reads back as exactly v, so that a written motor file parses to the same
// numbers (the calibration keeps the motor's text, and the model is rebuilt from it).
std::string num(double v) {
  char buf[64];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
  std::string out(buf, end);
  if (out.find_first_of(".eEn") == std::string::npos) out += ".0";  // keep TOML floats floats
  return out;
}

// A TOML basic string: quotes, backslashes and control characters escaped.
std::string toml_string(std::string_view text) {
  std::string out = "\"";
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20 || c == 0x7f) {
      char esc[8];
      std::snprintf(esc, sizeof esc, "\\u%04x", c);
      out += esc;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}
}  // namespace

std::string format_motor_file(const MotorFile& motor) {
  const MotorConstants<double>& c = motor.constants;
  std::ostringstream o;
  o << "# Motor description for lptn (see README.md, 'The motor file'). Keys carry their units.\n";
  o << "name = " << toml_string(motor.name) << "\n\n";
  o << "[nameplate]\npole_pairs = " << c.pole_pairs << "\nrated_frequency_hz = " << num(c.rated_frequency_hz)
    << "\nrated_voltage_v = " << num(c.rated_voltage_v) << "          # line, RMS\nrated_current_a = " << num(c.rated_current_a)
    << "           # phase, RMS\nrated_power_w = " << num(c.rated_power_w) << "\n\n";
  o << "[electrical]\nstator_resistance_20c_ohm = " << num(c.stator_resistance_20c_ohm)
    << "  # per phase\nstator_resistance_alpha_per_k = " << num(c.stator_resistance_alpha_per_k)
    << "\nrotor_resistance_20c_ohm = " << num(c.rotor_resistance_20c_ohm)
    << "   # referred to the stator\nrotor_resistance_alpha_per_k = " << num(c.rotor_resistance_alpha_per_k)
    << "\nmagnetizing_current_a = " << num(c.magnetizing_current_a) << "      # at rated flux\n\n";
  o << "[losses]\nstray_rated_w = " << num(c.stray_rated_w) << "\niron_rated_w = " << num(c.iron_rated_w)
    << "\niron_alpha = " << num(c.iron_alpha) << "\niron_beta = " << num(c.iron_beta) << "\nharmonic_frequency_hz = [";
  for (int i = 0; i < c.harmonic_points; ++i) o << (i ? ", " : "") << num(c.harmonic_frequency_hz[i]);
  o << "]\nharmonic_loss_w = [";
  for (int i = 0; i < c.harmonic_points; ++i) o << (i ? ", " : "") << num(c.harmonic_loss_w[i]);
  o << "]\n";
  for (int i = kKStemp; i <= kKPfe; ++i) {
    if (!motor.parameters[i].calibrate) o << param_spec(i).name << " = " << num(motor.parameters[i].initial) << "\n";
  }
  o << "\n[thermal]\ncapacitance_stator_winding_j_per_k = " << num(c.capacitance_j_per_k[0])
    << "\ncapacitance_stator_core_j_per_k = " << num(c.capacitance_j_per_k[1])
    << "\ncapacitance_rotor_winding_j_per_k = " << num(c.capacitance_j_per_k[2])
    << "\ncapacitance_rotor_core_j_per_k = " << num(c.capacitance_j_per_k[3])
    << "\nnominal_airflow_m3s = " << num(c.nominal_airflow_m3s) << "\nairflow_exponent = " << num(c.airflow_exponent)
    << "\nmin_airflow_fraction = " << num(c.min_airflow_fraction) << "\n";
  o << "\n# Calibrated parameters; `calibrate = false` pins one at `initial`.\n";
  for (int i = 0; i < kNumParams; ++i) {
    const ParameterSetting& s = motor.parameters[i];
    const bool loss_split = i >= kKStemp && i <= kKPfe;
    if (!s.in_file || (loss_split && !s.calibrate)) continue;
    o << "[parameters." << param_spec(i).name << "]   # " << param_spec(i).unit << ", " << param_spec(i).description
      << "\ninitial = " << num(s.initial) << "\nmin = " << num(s.min) << "\nmax = " << num(s.max) << "\n";
    if (!s.calibrate) o << "calibrate = false\n";
  }
  o << "\n[effects]\nenabled = [";
  bool first = true;
  for (int e = 0; e < kNumEffects; ++e) {
    if (motor.effects & effect_bit(e)) {
      o << (first ? "" : ", ") << '"' << EffectLibrary::kNames[e] << '"';
      first = false;
    }
  }
  o << "]\n";
  return o.str();
}

}  // namespace lptn
