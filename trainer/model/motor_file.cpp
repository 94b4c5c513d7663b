#include "trainer/model/motor_file.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <string_view>
#include <nlohmann/json.hpp>
#include <toml++/toml.h>
#include <type_traits>
#include <vector>

#include "trainer/data/did_you_mean.hpp"
#include "trainer/model/internal/motor_rules.hpp"

namespace lptn::model {
namespace {

using internal::constant_named;
using internal::constant_sections;
using internal::rule_broken;

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

  // The keys this table may hold, for "did you mean" when a required one is missing because it
  // was misspelt (the misspelling is then what is named, at its own line).
  void expect(std::vector<std::string> keys) { expected_ = std::move(keys); }

  double number(std::string_view key, bool required = true, double fallback = 0.0) {
    seen_.insert(std::string(key));
    const toml::node* node = table_.get(key);
    if (!node) {
      if (required) {
        refuse_misspelling_of(key);
        fail(file_, table_.source(), full(key), "missing (required)");
      }
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
    if (!node) {
      refuse_misspelling_of(key);
      fail(file_, table_.source(), full(key), "missing (required)");
    }
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
    if (!node) {
      refuse_misspelling_of(key);
      fail(file_, table_.source(), full(key), "missing table (required)");
    }
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
    std::vector<std::string> known(seen_.begin(), seen_.end());
    known.insert(known.end(), expected_.begin(), expected_.end());
    for (const auto& [key, node] : table_) {
      if (!seen_.count(std::string(key.str())))
        fail(file_, node.source(), full(key.str()), "unknown key" + data::did_you_mean(key.str(), known));
    }
  }

  toml::source_region where(std::string_view key) const {
    const toml::node* node = table_.get(key);
    return node ? node->source() : table_.source();
  }
  std::string full(std::string_view key) const { return prefix_.empty() ? std::string(key) : prefix_ + "." + std::string(key); }

 private:
  // A key of the table that is none of the expected ones and a typo of `missing`: refused as unknown.
  void refuse_misspelling_of(std::string_view missing) const {
    if (expected_.empty()) return;
    for (const auto& [key, node] : table_) {
      const std::string_view k = key.str();
      if (std::find(expected_.begin(), expected_.end(), k) != expected_.end()) continue;
      const std::string_view candidates[] = {missing};
      if (!data::closest_name(k, candidates).empty())
        fail(file_, node.source(), full(k), "unknown key" + data::did_you_mean(k, candidates));
    }
  }

  const toml::table& table_;
  std::string prefix_;
  const std::filesystem::path& file_;
  std::set<std::string> seen_;
  std::vector<std::string> expected_;
};

// Every key of a constants section (the loss-split factors of [losses] included).
std::vector<std::string> section_keys(std::string_view section) {
  std::vector<std::string> keys;
  const MotorConstants<double> c;
  for_each_motor_constant(
      [&](const MotorField& f, const auto&) {
        if (f.section != section || f.shape == FieldShape::table_size) return;
        if (f.shape == FieldShape::per_node) {
          for (const std::string_view k : f.node_keys) keys.emplace_back(k);
        } else {
          keys.emplace_back(f.name);
        }
      },
      c);
  if (section == "losses")
    for (int i = kKStemp; i <= kKPfe; ++i) keys.emplace_back(param_spec(i).name);
  return keys;
}

// Reads the constants of one section into c, each checked as its field says.
class ConstantsReader {
 public:
  ConstantsReader(TableReader& t, const std::filesystem::path& file) : t_(t), file_(file) {}

  void read(std::string_view section, MotorConstants<double>& c) {
    for_each_motor_constant(
        [&](const MotorField& f, auto& member) {
          if (f.section != section) return;
          using M = std::remove_reference_t<decltype(member)>;
          if constexpr (std::is_same_v<M, int>) {
            if (f.shape == FieldShape::table_size) {
              table_ = f;
              rows_ = &member;
              columns_.clear();
            } else {
              member = whole(f);
            }
          } else if constexpr (std::is_same_v<M, double>) {
            member = value(f, f.name, member);
            if (!f.below.empty() && !(member < constant_named(c, f.below)))
              fail(file_, t_.where(f.name), t_.full(f.name), "must be below " + std::string(f.below));
          } else if (f.shape == FieldShape::per_node) {
            for (int i = 0; i < kNumNodes; ++i) member[i] = value(f, f.node_keys[i], member[i]);
          } else {
            columns_.push_back({f, t_.numbers(f.name), member});
            if (static_cast<int>(columns_.size()) == table_.columns) read_table();
          }
        },
        c);
  }

 private:
  struct Column {
    MotorField field;
    std::vector<double> values;
    double* into;
  };

  double value(const MotorField& f, std::string_view key, double fallback) {
    const double v = t_.number(key, f.required, fallback);
    if (const char* why = rule_broken(f.rule, v, nullptr)) fail(file_, t_.where(key), t_.full(key), why);
    return v;
  }

  int whole(const MotorField& f) {
    const double v = value(f, f.name, 0.0);
    if (v != std::floor(v) || v > f.max_count)
      fail(file_, t_.where(f.name), t_.full(f.name), "must be a whole number from 1 to " + std::to_string(f.max_count));
    return static_cast<int>(v);
  }

  // Once every column of the table is read: equal lengths, 1 to max_count rows, each row's values
  // as their columns' rules say.
  void read_table() {
    const Column& first = columns_.front();
    for (const Column& col : columns_) {
      if (col.values.size() != first.values.size())
        fail(file_, t_.where(col.field.name), t_.full(col.field.name),
             "must have as many entries as " + t_.full(first.field.name));
    }
    const std::size_t rows = first.values.size();
    if (rows == 0 || rows > static_cast<std::size_t>(table_.max_count))
      fail(file_, t_.where(first.field.name), t_.full(first.field.name),
           "must have 1 to " + std::to_string(table_.max_count) + " entries");
    for (std::size_t i = 0; i < rows; ++i) {
      for (const Column& col : columns_) {
        if (const char* why = rule_broken(col.field.rule, col.values[i], i > 0 ? &col.values[i - 1] : nullptr))
          fail(file_, t_.where(col.field.name), t_.full(col.field.name), why);
        col.into[i] = col.values[i];
      }
    }
    *rows_ = static_cast<int>(rows);
  }

  TableReader& t_;
  const std::filesystem::path& file_;
  MotorField table_{};
  int* rows_ = nullptr;
  std::vector<Column> columns_;
};

// The loss-split factors live in [losses] unless [parameters.NAME] takes them over for calibration.
void read_loss_split(TableReader& t, const toml::table& losses, const toml::table& root,
                     const std::filesystem::path& file, MotorFile& motor) {
  const toml::table* params = root.get_as<toml::table>("parameters");
  for (int i = kKStemp; i <= kKPfe; ++i) {
    const std::string_view key = param_spec(i).name;
    const bool calibrated_instead = params && params->get(key);
    if (calibrated_instead) {
      if (losses.get(key))
        fail(file, t.where(key), "losses." + std::string(key),
             "given both here and as [parameters." + std::string(key) + "]; keep one");
      t.allow(key);
      continue;
    }
    const double v = i <= kKRtemp ? t.positive(key) : t.fraction(key);
    const ParamSpec& spec = param_spec(i);
    motor.parameters[i] = {v, std::min(spec.min, v), std::max(spec.max, v), false, true};
  }
}

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
  std::vector<std::string> top_keys{"name", "parameters", "effects"};
  for (const std::string_view section : constant_sections()) top_keys.emplace_back(section);
  top.expect(top_keys);
  top.allow("name");
  if (const toml::node* n = root.get("name")) {
    if (!n->is_string()) fail(shown_as, n->source(), "name", "must be a string");
    motor.name = n->value<std::string>().value_or("");
  }
  for (const std::string_view section : constant_sections()) {
    const toml::table& table = top.sub_table(section);
    TableReader t(table, std::string(section), shown_as);
    t.expect(section_keys(section));
    ConstantsReader(t, shown_as).read(section, motor.constants);
    if (section == "losses") read_loss_split(t, table, root, shown_as, motor);
    t.refuse_unknown();
  }
  if (const toml::table* params = top.optional_table("parameters")) {
    for (const auto& [key, node] : *params) {
      const std::string name(key.str());
      const int index = param_index(name);
      if (index < 0) {
        std::vector<std::string_view> known;
        for (int i = 0; i < kNumParams; ++i) known.push_back(param_spec(i).name);
        fail(shown_as, node.source(), "parameters." + name, "unknown parameter" + data::did_you_mean(name, known));
      }
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
      if (const internal::SettingProblem p = internal::setting_problem(index, s); !p.reason.empty())
        fail(shown_as, t.where(p.at), "parameters." + name + (p.key.empty() ? "" : "." + std::string(p.key)), p.reason);
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

InputKind input_kind(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // a byte order mark
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return InputKind::motor_toml;
  if (text[first] == '{') {
    const nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (!j.is_object()) return InputKind::other_json;
    if (j.contains("pooled") && j.contains("motors")) return InputKind::fleet_calibration_json;
    if (j.contains("parameters") && (j.contains("motor") || j.contains("metrics") || j.contains("created_utc")))
      return InputKind::calibration_json;
    return InputKind::other_json;
  }
  const std::string_view line = text.substr(first, text.find('\n', first) - first);
  if (line.find(',') != std::string_view::npos && line.find("time_s") != std::string_view::npos)
    return InputKind::cycle_csv;
  return InputKind::motor_toml;
}

std::string_view input_kind_words(InputKind kind) {
  switch (kind) {
    case InputKind::motor_toml: return "a motor file (TOML)";
    case InputKind::calibration_json: return "a calibration file (JSON)";
    case InputKind::fleet_calibration_json: return "a fleet calibration (JSON)";
    case InputKind::other_json: return "a JSON file";
    case InputKind::cycle_csv: return "a fleet-dump cycle (CSV)";
  }
  return "?";
}

MotorFile load_motor_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw MotorFileError(path.string() + ": is a directory, not a motor file (TOML)");
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw MotorFileError(path.string() +
                         (std::filesystem::exists(path, ec) ? ": cannot open the motor file" : ": no such motor file"));
  }
  std::ostringstream read;
  read << in.rdbuf();
  const std::string text = read.str();
  const InputKind kind = input_kind(text);
  const std::string what = path.string() + " is " + std::string(input_kind_words(kind)) + ", not a motor file (TOML)";
  switch (kind) {
    case InputKind::motor_toml: break;
    case InputKind::calibration_json: throw MotorFileError(what + ": give it as --calibration");
    case InputKind::fleet_calibration_json: throw MotorFileError(what + ": give it as --fleet");
    case InputKind::cycle_csv: throw MotorFileError(what + ": give it as --data");
    case InputKind::other_json: throw MotorFileError(what);
  }
  return parse_motor_file(text, path);
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

// One section's constants as key = value lines, in the order of their list.
void write_constants(std::ostream& o, std::string_view section, const MotorConstants<double>& c) {
  int rows = 0;
  for_each_motor_constant(
      [&](const MotorField& f, const auto& member) {
        if (f.section != section) return;
        using M = std::remove_cvref_t<decltype(member)>;
        if constexpr (std::is_same_v<M, int>) {
          if (f.shape == FieldShape::table_size) {
            rows = member;  // no key of its own: the length of the columns that follow
          } else {
            o << f.name << " = " << member << "\n";
          }
        } else if constexpr (std::is_same_v<M, double>) {
          o << f.name << " = " << num(member);
          if (!f.note.empty()) o << std::string(static_cast<std::size_t>(f.note_gap), ' ') << "# " << f.note;
          o << "\n";
        } else if (f.shape == FieldShape::per_node) {
          for (int i = 0; i < kNumNodes; ++i) o << f.node_keys[i] << " = " << num(member[i]) << "\n";
        } else {
          o << f.name << " = [";
          for (int i = 0; i < rows; ++i) o << (i ? ", " : "") << num(member[i]);
          o << "]\n";
        }
      },
      c);
}
}  // namespace

std::string format_motor_file(const MotorFile& motor) {
  std::ostringstream o;
  o << "# Motor description for lptn (see docs/model.md, 'The motor file'). Keys carry their units.\n";
  o << "name = " << toml_string(motor.name) << "\n";
  for (const std::string_view section : constant_sections()) {
    o << "\n[" << section << "]\n";
    write_constants(o, section, motor.constants);
    if (section != "losses") continue;
    for (int i = kKStemp; i <= kKPfe; ++i) {
      if (!motor.parameters[i].calibrate) o << param_spec(i).name << " = " << num(motor.parameters[i].initial) << "\n";
    }
  }
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

namespace internal {

std::vector<std::string_view> constant_sections() {
  std::vector<std::string_view> sections;
  const MotorConstants<double> c;
  for_each_motor_constant(
      [&](const MotorField& f, const auto&) {
        if (sections.empty() || sections.back() != f.section) sections.push_back(f.section);
      },
      c);
  return sections;
}

const char* rule_broken(FieldRule rule, double v, const double* previous) {
  switch (rule) {
    case FieldRule::finite: return nullptr;
    case FieldRule::positive: return v > 0 ? nullptr : "must be greater than zero";
    case FieldRule::non_negative: return v < 0 ? "must not be negative" : nullptr;
    case FieldRule::increasing: return previous && !(v > *previous) ? "must increase strictly" : nullptr;
  }
  return nullptr;
}

double constant_named(const MotorConstants<double>& c, std::string_view full_key) {
  double value = 0.0;
  for_each_motor_constant(
      [&](const MotorField& f, const auto& member) {
        if constexpr (std::is_same_v<std::remove_cvref_t<decltype(member)>, double>) {
          if (std::string(f.section) + "." + std::string(f.name) == full_key) value = member;
        }
      },
      c);
  return value;
}

SettingProblem setting_problem(int index, const ParameterSetting& s) {
  if (!(s.min < s.max)) return {"max", "max", "must be greater than min (bounds swapped?)"};
  if (s.initial < s.min || s.initial > s.max) return {"initial", "initial", "must lie within [min, max]"};
  const ParamSpec& spec = param_spec(index);
  if (spec.min > 0 && s.min <= 0) return {"min", "min", "must be greater than zero (" + std::string(spec.unit) + ", log scale)"};
  if (index >= kKStray && index <= kKPfe && (s.min < 0 || s.max > 1)) return {"max", "", "a share must stay within [0, 1]"};
  return {};
}

}  // namespace internal
}  // namespace lptn::model
