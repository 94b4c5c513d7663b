// export_header() and its literals: exact numbers, safe strings, clear refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "lptn_testing/sample_result.hpp"
#include "lptn_testing/distinct_motor_constants.hpp"
#include "tools/export/cpp_literals.hpp"
#include "tools/export/export_header.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::exporter {
namespace {

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const exporter::ExportError& e) {
    return e.what();
  }
  return "";
}

TEST(CppLiterals, DoublesReadBackExactly) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> mantissa(1.0, 10.0);
  std::uniform_int_distribution<int> exponent(-30, 30);
  for (int i = 0; i < 10000; ++i) {
    const double v = mantissa(rng) * std::pow(10.0, exponent(rng)) * (i % 2 ? -1 : 1);
    const std::string s = exporter::double_literal(v, "v");
    EXPECT_EQ(std::strtod(s.c_str(), nullptr), v) << s;
  }
  EXPECT_EQ(exporter::double_literal(24, "v"), "24.0");  // a floating literal, not an int
  EXPECT_EQ(exporter::double_literal(0.1, "v"), "0.1");
  EXPECT_EQ(exporter::double_literal(1e300, "v"), "1e+300");
  EXPECT_THROW(exporter::double_literal(std::nan(""), "v"), std::invalid_argument);
  EXPECT_THROW(exporter::double_literal(std::numeric_limits<double>::infinity(), "v"), std::invalid_argument);
}

TEST(CppLiterals, FloatsReadBackExactlyAsFloat) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> d(-2.0f, 2.0f);
  for (int i = 0; i < 10000; ++i) {
    const float v = d(rng);
    const std::string s = exporter::float_literal(v, "v");
    ASSERT_EQ(s.back(), 'f');
    EXPECT_EQ(std::strtof(s.c_str(), nullptr), v) << s;
  }
  EXPECT_EQ(exporter::float_literal(1.0f, "v"), "1.0f");
  EXPECT_EQ(exporter::float_literal(1e-7f / 3, "v"), "3.3333333e-08f");
}

TEST(CppLiterals, StringsAndComments) {
  EXPECT_EQ(exporter::string_literal("a\"b\\c"), "\"a\\\"b\\\\c\"");
  EXPECT_EQ(exporter::string_literal("x\ny\x01" "9"), "\"x\\012y\\0019\"");  // octal: never swallows a digit
  EXPECT_EQ(exporter::string_literal("\xc3\xbc"), "\"\\303\\274\"");
  EXPECT_EQ(exporter::comment_text("a\nb\r\tc\\"), "a b  c/");  // no line break, no splice
}

TEST(ExportHeader, HasEverySection) {
  const calibrate::CalibrationResult c = testing::sample_result();
  const std::string h = exporter::export_header(c, {"cal.json", true});
  for (const char* s : {"#pragma once", "#include \"lptn/model.hpp\"", "#include \"lptn/motor_constants.hpp\"",
                        "#include \"lptn/actor.hpp\"", "namespace lptn::calibration {", "kMethod[] = \"lm\"",
                        "kSourceFile[] = \"cal.json\"",
                        "kEffects = effect_bit(effect_index(\"airgap\")) | effect_bit(effect_index(\"sensor_lag\"))",
                        "static_assert(param_index(\"lambda_1s\") == 0", "ParamVector<double> kParams = {{",
                        "constexpr MotorConstants<double> motor_constants()", "m.harmonic_loss_w[4] = 900.0;",
                        "kHasRotorMetrics = false", "alignas(16) inline constexpr float kActorW1[]",
                        "inline constexpr ActorView kActor{2, 3, 2, kActorW1", "kActorChecks = 2;"})
    EXPECT_NE(h.find(s), std::string::npos) << s;
  EXPECT_NE(h.find("kCalibrationFormatVersion = " + std::to_string(calibrate::kCalibrationFormatVersion) + ";"), std::string::npos);
  EXPECT_NE(h.find("// [1] lambda_2s [W/K] (calibrated)"), std::string::npos);  // NaN std_error: none shown
  EXPECT_NE(h.find("// [0] lambda_1s [W/K] +- 0.00143 (calibrated)"), std::string::npos);

  const std::string without = exporter::export_header(c, {"cal.json", false});
  EXPECT_EQ(without.find("actor"), std::string::npos);
  EXPECT_EQ(without.find("kActor"), std::string::npos);
}

// A failed calibration is refused, on one line that says why (its warnings' messages).
TEST(ExportHeader, RefusesAFailedCalibration) {
  calibrate::CalibrationResult c = testing::sample_result();
  c.status = calibrate::kStatusFailed;
  c.warnings = {{"not_converged", "the fit did not converge in 60 iterations", {}},
                {"at_bound", "lambda_1s ended at its lower bound 1 W/K", {"lambda_1s"}}};
  const std::string e = error_of([&] { exporter::export_header(c, {"cal.json", false}); });
  EXPECT_EQ(e, "cal.json: status 'failed', not exported: the fit did not converge in 60 iterations; lambda_1s ended at "
               "its lower bound 1 W/K");
  c.status = calibrate::kStatusWarnings;
  EXPECT_EQ(error_of([&] { exporter::export_header(c, {"cal.json", false}); }), "");
}

// Warnings are comments in the header; a parameter the data could not pin says so, and carries
// no standard error; a calibrated one its standard error.
TEST(ExportHeader, CarriesWarningsAndEachParametersSpread) {
  calibrate::CalibrationResult c = testing::sample_result();
  c.status = calibrate::kStatusWarnings;
  c.warnings = {{"not_identifiable", "lambda_1r is not identifiable from this data: no rotor readings", {"lambda_1r"}}};
  calibrate::ParameterResult& r = c.parameters[3];
  r.identifiable = false;
  r.calibrated = false;
  r.std_error = std::nan("");
  c.parameters[0].calibrated = true;
  c.parameters[0].std_error = 0.25;
  c.parameters[0].value = 25.0;
  const std::string h = exporter::export_header(c, {"cal.json", false});
  EXPECT_NE(h.find("//   status       warnings, read these warnings first:\n"), std::string::npos);
  EXPECT_NE(h.find("//   warning      not_identifiable: lambda_1r is not identifiable from this data: no rotor readings\n"),
            std::string::npos);
  EXPECT_NE(h.find("// [3] lambda_1r [W/K] (not identifiable from this data: the motor file's value)\n"), std::string::npos);
  EXPECT_EQ(h.find("// [3] lambda_1r [W/K] (calibrated)"), std::string::npos);
  EXPECT_NE(h.find("inline constexpr double kParamStdError[kNumParams] = {\n    0.25,  // [0] lambda_1s\n"), std::string::npos);
  EXPECT_NE(h.find("    -1.0,  // [3] lambda_1r\n"), std::string::npos);  // none known
  EXPECT_NE(h.find("inline constexpr bool kParamIdentifiable[kNumParams] = {true, true, true, false, "), std::string::npos);
}

// Every constant in the field list is in motor_constants(), with its value; a table's rows up to
// its size (the tail stays zero).
TEST(ExportHeader, WritesEveryMotorConstant) {
  model::MotorFile motor = testing::example_motor();
  motor.constants = testing::distinct_motor_constants();
  const std::string h = exporter::export_header(testing::sample_result(motor), {});
  int rows = 0;
  for_each_motor_constant(
      [&](const MotorField& f, const auto& v) {
        const std::string name(f.name);
        using M = std::remove_cvref_t<decltype(v)>;
        std::vector<std::string> lines;
        if constexpr (std::is_same_v<M, int>) {
          lines.push_back("  m." + name + " = " + std::to_string(v) + ";\n");
          if (f.shape == FieldShape::table_size) rows = v;
        } else if constexpr (std::is_same_v<M, double>) {
          lines.push_back("  m." + name + " = " + exporter::double_literal(v, name) + ";\n");
        } else {
          const int n = f.shape == FieldShape::table_column ? rows : static_cast<int>(std::size(v));
          for (int i = 0; i < n; ++i)
            lines.push_back("  m." + name + "[" + std::to_string(i) + "] = " + exporter::double_literal(v[i], name) + ";");
        }
        for (const std::string& line : lines) EXPECT_NE(h.find(line), std::string::npos) << line;
      },
      motor.constants);
}

TEST(ExportHeader, NoEffectsIsZero) {
  calibrate::CalibrationResult c = testing::sample_result();
  c.effects = 0;
  EXPECT_NE(exporter::export_header(c, {}).find("kEffects = 0;  // the paper's model only"), std::string::npos);
}

TEST(ExportHeader, Refusals) {
  calibrate::CalibrationResult c = testing::sample_result();
  c.has_actor = false;
  EXPECT_EQ(error_of([&] { exporter::export_header(c, {"cal.json", true}); }),
            "cal.json: --actor: this calibration has no actor (method 'lm'; only td3-paper and td3-episode keep one: their actor maps speed and torque to parameters)");

  c = testing::sample_result();
  c.actor.layers.pop_back();
  EXPECT_NE(error_of([&] { exporter::export_header(c, {"cal.json", true}); }).find("cal.json: field 'actor.layers'"), std::string::npos);

  c = testing::sample_result();
  c.actor.check_obs.clear();
  c.actor.check_actions.clear();
  EXPECT_NE(error_of([&] { exporter::export_header(c, {"cal.json", true}); }).find("cal.json: field 'actor.check_obs': empty"),
            std::string::npos);

  c = testing::sample_result();
  c.parameters[2].value = std::nan("");
  EXPECT_EQ(error_of([&] { exporter::export_header(c, {"cal.json", false}); }),
            "cal.json: parameters.lambda_12s.value: nan has no C++ literal");
}

}  // namespace
}  // namespace lptn::exporter
