#include "trainer/model/motor_json.hpp"

#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include "trainer/model/internal/motor_rules.hpp"

namespace lptn::model {
namespace {

using nlohmann::ordered_json;

ordered_json constants_json(std::string_view section, const MotorConstants<double>& c) {
  ordered_json out = ordered_json::object();
  int rows = 0;
  for_each_motor_constant(
      [&](const MotorField& f, const auto& member) {
        if (f.section != section) return;
        using M = std::remove_cvref_t<decltype(member)>;
        const std::string key(f.name);
        if constexpr (std::is_same_v<M, int>) {
          if (f.shape == FieldShape::table_size) {
            rows = member;  // no key of its own: the length of the columns that follow
          } else {
            out[key] = member;
          }
        } else if constexpr (std::is_same_v<M, double>) {
          out[key] = member;
        } else if (f.shape == FieldShape::per_node) {
          for (int i = 0; i < kNumNodes; ++i) out[std::string(f.node_keys[i])] = member[i];
        } else {
          out[key] = std::vector<double>(member, member + rows);
        }
      },
      c);
  return out;
}

// One section's constants into c, each checked as its field says (as the motor file's reader does).
void read_constants(const hostio::JsonField& section_field, std::string_view section, MotorConstants<double>& c) {
  section_field.expect_object();
  std::set<std::string> known;
  MotorField table{};
  int* rows = nullptr;
  struct Column {
    hostio::JsonField field;
    FieldRule rule;
    double* into;
  };
  std::vector<Column> columns;
  auto value = [&](const MotorField& f, std::string_view key, double fallback) {
    const std::string k(key);
    known.insert(k);
    if (!section_field.has(k.c_str()) && !f.required) return fallback;
    const hostio::JsonField v = section_field[k.c_str()];
    const double x = v.number();
    if (const char* why = internal::rule_broken(f.rule, x, nullptr)) v.fail(why);
    return x;
  };
  for_each_motor_constant(
      [&](const MotorField& f, auto& member) {
        if (f.section != section) return;
        using M = std::remove_reference_t<decltype(member)>;
        const std::string key(f.name);
        if constexpr (std::is_same_v<M, int>) {
          if (f.shape == FieldShape::table_size) {
            table = f;
            rows = &member;
            columns.clear();
          } else {
            known.insert(key);
            const hostio::JsonField v = section_field[key.c_str()];
            const long long n = v.integer();
            if (n < 1 || n > f.max_count) v.fail("must be a whole number from 1 to " + std::to_string(f.max_count));
            member = static_cast<int>(n);
          }
        } else if constexpr (std::is_same_v<M, double>) {
          member = value(f, f.name, member);
          if (!f.below.empty() && !(member < internal::constant_named(c, f.below)))
            section_field[key.c_str()].fail("must be below " + std::string(f.below));
        } else if (f.shape == FieldShape::per_node) {
          for (int i = 0; i < kNumNodes; ++i) member[i] = value(f, f.node_keys[i], member[i]);
        } else {
          known.insert(key);
          columns.push_back({section_field[key.c_str()], f.rule, member});
          if (static_cast<int>(columns.size()) < table.columns) return;
          // Every column of the table read: equal lengths, 1 to max_count rows, each row as its rule says.
          const std::size_t n = columns.front().field.size();
          for (const Column& col : columns)
            if (col.field.size() != n) col.field.fail("must have as many entries as " + columns.front().field.path());
          if (n == 0 || n > static_cast<std::size_t>(table.max_count))
            columns.front().field.fail("must have 1 to " + std::to_string(table.max_count) + " entries");
          for (const Column& col : columns) {
            for (std::size_t i = 0; i < n; ++i) {
              col.into[i] = col.field.at(i).number();
              if (const char* why = internal::rule_broken(col.rule, col.into[i], i > 0 ? &col.into[i - 1] : nullptr))
                col.field.at(i).fail(why);
            }
          }
          *rows = static_cast<int>(n);
        }
      },
      c);
  for (const auto& [key, v] : section_field.json().items())
    if (!known.count(key)) section_field[key.c_str()].fail("unknown key");
}

}  // namespace

ordered_json motor_json(const MotorFile& motor) {
  ordered_json j;
  j["name"] = motor.name;
  ordered_json& constants = j["constants"] = ordered_json::object();
  for (const std::string_view section : internal::constant_sections())
    constants[std::string(section)] = constants_json(section, motor.constants);
  ordered_json& parameters = j["parameters"] = ordered_json::object();
  for (int i = 0; i < kNumParams; ++i) {
    const ParameterSetting& s = motor.parameters[static_cast<std::size_t>(i)];
    if (!s.in_file) continue;
    parameters[std::string(param_spec(i).name)] = {{"initial", s.initial}, {"min", s.min}, {"max", s.max}, {"calibrate", s.calibrate}};
  }
  j["effects"] = ordered_json::array();
  for (int e = 0; e < kNumEffects; ++e)
    if (motor.effects & effect_bit(e)) j["effects"].push_back(std::string(EffectLibrary::kNames[e]));
  return j;
}

MotorFile motor_from_json(const hostio::JsonField& motor_field) {
  MotorFile motor;
  motor.name = motor_field["name"].string();
  motor.parameters = default_parameter_settings();
  const hostio::JsonField constants = motor_field["constants"];
  std::set<std::string> sections;
  for (const std::string_view section : internal::constant_sections()) {
    const std::string key(section);
    sections.insert(key);
    read_constants(constants[key.c_str()], section, motor.constants);
  }
  for (const auto& [key, v] : constants.json().items())
    if (!sections.count(key)) constants[key.c_str()].fail("unknown section");
  const hostio::JsonField parameters = motor_field["parameters"];
  parameters.expect_object();
  for (const auto& [name, v] : parameters.json().items()) {
    const hostio::JsonField p = parameters[name.c_str()];
    const int index = param_index(name);
    if (index < 0) p.fail("unknown parameter");
    ParameterSetting& s = motor.parameters[static_cast<std::size_t>(index)];
    s.initial = p["initial"].number();
    s.min = p["min"].number();
    s.max = p["max"].number();
    s.calibrate = p["calibrate"].boolean();
    s.in_file = true;
    if (const internal::SettingProblem problem = internal::setting_problem(index, s); !problem.reason.empty())
      (problem.key.empty() ? p : p[std::string(problem.key).c_str()]).fail(problem.reason);
  }
  const hostio::JsonField effects = motor_field["effects"];
  for (std::size_t i = 0; i < effects.size(); ++i) {
    const std::string name = effects.at(i).string();
    const int e = effect_index(name);
    if (e < 0) effects.at(i).fail("unknown effect '" + name + "'");
    motor.effects |= effect_bit(e);
  }
  return motor;
}

}  // namespace lptn::model
