// The motor file: the contract's example loads; every mistake is named by file, line and key.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "lptn_testing/distinct_motor_constants.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::model {
namespace {

std::string example_text() {
  std::ifstream in(LPTN_CONTRACT_EXAMPLE);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

// The 1-based line on which `needle` first appears.
int line_of(const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

std::string error_of(const std::string& text) {
  try {
    model::parse_motor_file(text, "motor.toml");
  } catch (const model::MotorFileError& e) {
    return e.what();
  }
  return "no error";
}

TEST(MotorFile, TheContractExampleLoads) {
  const model::MotorFile m = model::parse_motor_file(example_text(), "motor.toml");
  EXPECT_EQ(m.constants.pole_pairs, 2);
  EXPECT_DOUBLE_EQ(m.constants.rated_voltage_v, 1900.0);
  EXPECT_EQ(m.constants.harmonic_points, 5);
  EXPECT_DOUBLE_EQ(m.constants.harmonic_loss_w[2], 1700.0);
  EXPECT_DOUBLE_EQ(m.constants.capacitance_j_per_k[1], 240e3);
  EXPECT_DOUBLE_EQ(m.parameters[kLambda12r].initial, 200.0);
  EXPECT_DOUBLE_EQ(m.parameters[kLambda12r].max, 5000.0);
  EXPECT_TRUE(m.parameters[kLambda1s].calibrate);
  EXPECT_FALSE(m.parameters[kKStray].calibrate);  // given under [losses]: fixed
  EXPECT_DOUBLE_EQ(m.parameters[kKStray].initial, 0.6);
  EXPECT_EQ(m.effects, 0u);
}

TEST(MotorFile, RoundTripsThroughItsOwnFormat) {
  model::MotorFile m = model::parse_motor_file(example_text(), "motor.toml");
  m.effects = effect_bit(effect_index("windage")) | effect_bit(effect_index("sensor_lag"));
  m.parameters[param_index("windage_base_w")] = {450.0, 10.0, 9000.0, true, true};
  m.parameters[kKHarm] = {0.4, 0.1, 0.9, true, true};
  const model::MotorFile back = model::parse_motor_file(model::format_motor_file(m), "again.toml");
  EXPECT_EQ(back.effects, m.effects);
  for (int i = 0; i < kNumParams; ++i) {
    EXPECT_DOUBLE_EQ(back.parameters[i].initial, m.parameters[i].initial) << param_spec(i).name;
    EXPECT_EQ(back.parameters[i].calibrate, m.parameters[i].calibrate) << param_spec(i).name;
  }
  EXPECT_DOUBLE_EQ(back.parameters[param_index("windage_base_w")].max, 9000.0);
  EXPECT_DOUBLE_EQ(back.constants.iron_rated_w, m.constants.iron_rated_w);
}

// What the parser accepts, the writer writes back exactly: any name (quotes, backslashes, control
// characters), and every number to the last bit (the calibration rebuilds its model from the text).
TEST(MotorFile, WritesBackAnyNameAndEveryNumberExactly) {
  model::MotorFile m = model::parse_motor_file(example_text(), "motor.toml");
  m.name = "say \"hi\" \\ tab\there\nnewline \x7f unicode \xc3\xa9";
  m.parameters[kLambda1s] = {1.0 + 0.1 + 0.2, 1.0 / 3.0, 1e300, true, true};
  m.constants.iron_rated_w = 1234.5678901234567;
  const model::MotorFile back = model::parse_motor_file(model::format_motor_file(m), "again.toml");
  EXPECT_EQ(back.name, m.name);
  EXPECT_EQ(back.parameters[kLambda1s].initial, 1.0 + 0.1 + 0.2);
  EXPECT_EQ(back.parameters[kLambda1s].min, 1.0 / 3.0);
  EXPECT_EQ(back.parameters[kLambda1s].max, 1e300);
  EXPECT_EQ(back.constants.iron_rated_w, m.constants.iron_rated_w);
}

// Every constant in the field list goes out and comes back; one the writer or the reader missed
// would come back as its default (distinct_motor_constants() holds none).
TEST(MotorFile, EveryConstantRoundTrips) {
  model::MotorFile m = model::parse_motor_file(example_text(), "motor.toml");
  m.constants = testing::distinct_motor_constants();
  const model::MotorFile back = model::parse_motor_file(model::format_motor_file(m), "again.toml");
  int compared = 0;
  for_each_motor_constant(
      [&](const MotorField& f, const auto& got, const auto& want) {
        if constexpr (std::is_array_v<std::remove_cvref_t<decltype(got)>>) {
          for (std::size_t i = 0; i < std::size(got); ++i) EXPECT_EQ(got[i], want[i]) << f.name << "[" << i << "]";
        } else {
          EXPECT_EQ(got, want) << f.name;
        }
        ++compared;
      },
      back.constants, m.constants);
  EXPECT_GT(compared, 20);
}

// Every key of every constant is read: without a required one the reader names it; without an
// optional one it keeps the default.
TEST(MotorFile, EveryConstantsKeyIsRead) {
  const std::string full = model::format_motor_file(model::parse_motor_file(example_text(), "motor.toml"));
  const MotorConstants<double> defaults;
  for_each_motor_constant(
      [&](const MotorField& f, const auto&) {
        std::vector<std::string_view> keys;
        if (f.shape == FieldShape::per_node) keys.assign(std::begin(f.node_keys), std::end(f.node_keys));
        else if (f.shape != FieldShape::table_size) keys.push_back(f.name);
        for (const std::string_view key : keys) {
          const std::string line = "\n" + std::string(key) + " = ";
          const auto at = full.find(line);
          ASSERT_NE(at, std::string::npos) << key << " not written";
          std::string text = full;
          text.erase(at, full.find('\n', at + 1) - at);
          const std::string message = error_of(text);
          if (f.required) {
            EXPECT_NE(message.find("key '" + std::string(f.section) + "." + std::string(key) + "': missing (required)"),
                      std::string::npos)
                << message;
          } else {
            EXPECT_EQ(message, "no error") << key;
          }
        }
      },
      defaults);
}

struct BadCase {
  const char* what;
  std::string from, to;
  std::string key;     // must be named
  std::string reason;  // must appear
  std::string at;      // text whose line must be named
};

TEST(MotorFile, EveryMistakeNamesFileLineAndKey) {
  const std::string ok = example_text();
  const BadCase cases[] = {
      {"unknown key", "iron_beta = 2.0", "iron_beta = 2.0\niron_gamma = 1.0", "losses.iron_gamma", "unknown key", "iron_gamma"},
      {"unknown top-level key", "name = ", "colour = \"red\"\nname = ", "colour", "unknown key", "colour"},
      {"missing key", "rated_current_a = 115.0           # phase, RMS\n", "", "nameplate.rated_current_a", "missing", "[nameplate]"},
      {"negative capacitance", "capacitance_rotor_core_j_per_k = 110e3", "capacitance_rotor_core_j_per_k = -110e3",
       "thermal.capacitance_rotor_core_j_per_k", "greater than zero", "capacitance_rotor_core_j_per_k"},
      {"swapped bounds", "initial = 40.0\nmin = 1.0\nmax = 1000.0", "initial = 40.0\nmin = 1000.0\nmax = 1.0",
       "parameters.lambda_1s.max", "bounds swapped", "max = 1.0"},
      {"initial outside bounds", "initial = 100.0", "initial = 5000.0", "parameters.lambda_2s.initial", "within", "initial = 5000.0"},
      {"unknown parameter", "[parameters.lambda_1s]", "[parameters.lambda_9s]", "parameters.lambda_9s", "unknown parameter", "[parameters.lambda_9s]"},
      {"unknown effect", "enabled = []", "enabled = [\"warp_drive\"]", "effects.enabled", "warp_drive", "enabled ="},
      {"not a number", "rated_power_w = 310e3", "rated_power_w = \"big\"", "nameplate.rated_power_w", "number", "rated_power_w"},
      {"table lengths differ", "harmonic_loss_w = [1100.0, 1400.0, 1700.0, 1400.0, 900.0]", "harmonic_loss_w = [1100.0, 1400.0]",
       "losses.harmonic_loss_w", "as many entries", "harmonic_loss_w"},
      {"share above one", "k_pfe = 0.85", "k_pfe = 1.85", "losses.k_pfe", "between 0 and 1", "k_pfe"},
      {"loss split twice", "[effects]", "[parameters.k_pfe]\ninitial = 0.8\nmin = 0.5\nmax = 1.0\n[effects]", "losses.k_pfe",
       "both", "k_pfe = 0.85"},
  };
  for (const BadCase& c : cases) {
    const std::string text = replace(ok, c.from, c.to);
    const std::string message = error_of(text);
    EXPECT_NE(message.find("motor.toml:" + std::to_string(line_of(text, c.at)) + ":"), std::string::npos)
        << c.what << ": " << message;
    EXPECT_NE(message.find("'" + c.key + "'"), std::string::npos) << c.what << ": " << message;
    EXPECT_NE(message.find(c.reason), std::string::npos) << c.what << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << c.what;
  }
}

TEST(MotorFile, SyntaxErrorsNameTheLine) {
  const std::string text = replace(example_text(), "pole_pairs = 2", "pole_pairs = = 2");
  const std::string message = error_of(text);
  EXPECT_NE(message.find("motor.toml:" + std::to_string(line_of(text, "pole_pairs = = 2")) + ":"), std::string::npos) << message;
}

TEST(MotorFile, EffectsEnableByNameWithLibraryDefaults) {
  const model::MotorFile m = model::parse_motor_file(replace(example_text(), "enabled = []", "enabled = [\"airgap\", \"sensor_lag\"]"), "m.toml");
  EXPECT_EQ(m.effects, effect_bit(effect_index("airgap")) | effect_bit(effect_index("sensor_lag")));
  EXPECT_EQ(m.model().num_states(), 5);
  EXPECT_DOUBLE_EQ(m.parameters[param_index("airgap_lambda")].initial, param_spec(param_index("airgap_lambda")).initial);
}

}  // namespace
}  // namespace lptn::model
