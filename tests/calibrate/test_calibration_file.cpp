// calibration.json: everything written comes back exactly; every kind of bad file gets one line
// naming the file and the line or the field.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "lptn_testing/error_metrics.hpp"
#include "lptn_testing/sample_result.hpp"
#include "lptn_testing/temp_dir.hpp"
#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::calibrate {
namespace {

// The motor file's text as kept (provenance only from format 3 on): escaped and read back whole.
const std::string kMotorText = "name = \"m\"\n# ünïcode, \"quotes\", \\backslash\\ and a tab\t\n";

calibrate::CalibrationResult sample() {
  calibrate::CalibrationResult r = testing::sample_result();
  r.motor.text = kMotorText;
  r.motor.effects = effect_bit(effect_index("airgap"));  // the file's own, beside the calibration's two
  return r;
}

void expect_split_eq(const calibrate::SplitMetrics& a, const calibrate::SplitMetrics& b) {
  testing::expect_same_metrics(a.stator, b.stator, "stator");
  testing::expect_same_metrics(a.rotor, b.rotor, "rotor");
  ASSERT_EQ(a.cycles.size(), b.cycles.size());
  for (std::size_t i = 0; i < a.cycles.size(); ++i) {
    EXPECT_EQ(a.cycles[i].name, b.cycles[i].name);
    testing::expect_same_metrics(a.cycles[i].stator, b.cycles[i].stator, a.cycles[i].name);
    testing::expect_same_metrics(a.cycles[i].rotor, b.cycles[i].rotor, a.cycles[i].name);
  }
}

using testing::slurp;

// The message of the CalibrationFileError that `f` throws ("" if none).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const calibrate::CalibrationFileError& e) {
    return e.what();
  }
  return "";
}

std::string error_for(const nlohmann::json& j) {
  return error_of([&] { calibrate::calibration_from_json(j, "cal.json"); });
}

TEST(CalibrationFile, RoundTripKeepsEveryField) {
  testing::TempDir t;
  const calibrate::CalibrationResult a = sample();
  const auto path = t.path() / "calibration.json";
  calibrate::save_calibration(a, path);
  const calibrate::CalibrationResult b = calibrate::load_calibration(path);

  EXPECT_EQ(b.format_version, calibrate::kCalibrationFormatVersion);
  EXPECT_EQ(b.created_utc, a.created_utc);
  EXPECT_EQ(b.lptn_version, a.lptn_version);
  EXPECT_EQ(b.motor.name, a.motor.name);
  EXPECT_EQ(b.motor.path, a.motor.path);
  EXPECT_EQ(b.motor.text, a.motor.text);
  // The motor whole: constants to the bit, parameter settings and effects, as its file would say.
  EXPECT_EQ(model::format_motor_file(b.motor), model::format_motor_file(a.motor));
  EXPECT_EQ(b.motor.effects, a.motor.effects);
  EXPECT_EQ(b.effects, a.effects);
  ASSERT_EQ(b.parameters.size(), static_cast<std::size_t>(kNumParams));
  for (int i = 0; i < kNumParams; ++i) {
    const calibrate::ParameterResult &p = a.parameters[i], &q = b.parameters[i];
    EXPECT_EQ(q.name, p.name);
    EXPECT_EQ(q.unit, p.unit);
    EXPECT_EQ(q.value, p.value) << p.name;  // bit for bit
    EXPECT_EQ(q.initial, p.initial);
    EXPECT_EQ(q.min, p.min);
    EXPECT_EQ(q.max, p.max);
    EXPECT_EQ(q.calibrated, p.calibrated);
    if (std::isnan(p.std_error)) EXPECT_TRUE(std::isnan(q.std_error)) << p.name;
    else EXPECT_EQ(q.std_error, p.std_error) << p.name;
  }
  EXPECT_EQ(b.values(), a.values());
  ASSERT_EQ(b.correlated.size(), a.correlated.size());
  for (std::size_t i = 0; i < a.correlated.size(); ++i) {
    EXPECT_EQ(b.correlated[i].a, a.correlated[i].a);
    EXPECT_EQ(b.correlated[i].b, a.correlated[i].b);
    EXPECT_EQ(b.correlated[i].correlation, a.correlated[i].correlation);
  }
  EXPECT_EQ(b.method, a.method);
  EXPECT_EQ(b.settings, a.settings);
  EXPECT_EQ(b.details, a.details);
  EXPECT_EQ(b.seconds, a.seconds);
  ASSERT_EQ(b.data.size(), a.data.size());
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    EXPECT_EQ(b.data[i].cycle, a.data[i].cycle);
    EXPECT_EQ(b.data[i].file, a.data[i].file);
    EXPECT_EQ(b.data[i].sha256, a.data[i].sha256);
  }
  EXPECT_EQ(b.data_sha256, a.data_sha256);
  EXPECT_EQ(b.train_cycles, a.train_cycles);
  EXPECT_EQ(b.test_cycles, a.test_cycles);
  EXPECT_EQ(b.split_rule, a.split_rule);
  expect_split_eq(b.train, a.train);
  expect_split_eq(b.test, a.test);

  ASSERT_TRUE(b.has_actor);
  EXPECT_EQ(b.actor.obs_offset, a.actor.obs_offset);
  EXPECT_EQ(b.actor.obs_scale, a.actor.obs_scale);
  ASSERT_EQ(b.actor.layers.size(), a.actor.layers.size());
  for (std::size_t l = 0; l < a.actor.layers.size(); ++l) {
    EXPECT_EQ(b.actor.layers[l].in, a.actor.layers[l].in);
    EXPECT_EQ(b.actor.layers[l].out, a.actor.layers[l].out);
    EXPECT_EQ(b.actor.layers[l].weight, a.actor.layers[l].weight);  // floats bit for bit
    EXPECT_EQ(b.actor.layers[l].bias, a.actor.layers[l].bias);
  }
  EXPECT_EQ(b.actor.param_indices, a.actor.param_indices);
  EXPECT_EQ(b.actor.check_obs, a.actor.check_obs);
  EXPECT_EQ(b.actor.check_actions, a.actor.check_actions);
}

TEST(CalibrationFile, LayoutAsDocumented) {
  testing::TempDir t;
  calibrate::CalibrationResult a = sample();
  const auto path = t.path() / "calibration.json";
  calibrate::save_calibration(a, path);
  const std::string text = slurp(path);
  // The file reads top-down: the version first, parameters in model order.
  EXPECT_EQ(text.find("\"format_version\""), 4u);
  EXPECT_LT(text.find("\"lambda_1s\""), text.find("\"lambda_2s\""));
  EXPECT_LT(text.find("\"k_pfe\""), text.find("\"airgap_lambda\""));
  EXPECT_NE(text.find("\"std_error\": null"), std::string::npos);  // NaN is null
  EXPECT_NE(text.find("-0.3,"), std::string::npos);                // floats in their short form
  const auto j = nlohmann::json::parse(text);
  EXPECT_EQ(j["effects"], nlohmann::json({"airgap", "sensor_lag"}));
  EXPECT_EQ(j["parameters"][0]["unit"], "W/K");
  EXPECT_EQ(j["metrics"]["train"]["samples_rotor"], 35000);
  EXPECT_FALSE(j["metrics"]["test"].contains("rmse_rotor_k"));  // rotor not measured on the test side
  EXPECT_EQ(j["actor"]["param_names"], nlohmann::json({"lambda_1s", "airgap_lambda"}));
  EXPECT_EQ(nlohmann::json::parse(text), calibrate::to_json(a));

  a.has_actor = false;
  calibrate::save_calibration(a, path);
  EXPECT_FALSE(nlohmann::json::parse(slurp(path)).contains("actor"));
  EXPECT_FALSE(calibrate::load_calibration(path).has_actor);
}

TEST(CalibrationFile, BadJsonNamesTheLine) {
  testing::TempDir t;
  const auto path = t.path() / "cal.json";
  std::ofstream(path) << "{\n  \"format_version\": 1,\n  \"motor\": {\"name\": \"m\",\n";  // cut short
  const std::string e = error_of([&] { calibrate::load_calibration(path); });
  EXPECT_EQ(e.rfind(path.string() + ": line 4: ", 0), 0u) << e;
  EXPECT_NE(e.find("unexpected end of input"), std::string::npos) << e;
  EXPECT_EQ(e.find("json.exception"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;

  // A number beyond a double: nlohmann throws another exception (out_of_range, no position) for it,
  // which escaped the reader until the fuzzer found it (fuzz_motor_json).
  std::ofstream(path) << "{\n  \"format_version\": 3,\n  \"seconds\": 1e400\n}\n";
  EXPECT_EQ(error_of([&] { calibrate::load_calibration(path); }), path.string() + ": line 3: number overflow parsing '1e400'");

  std::ofstream(path) << "{\n  \"a\": 1,\n  \"b\": ]\n}\n";
  const std::string e2 = error_of([&] { calibrate::load_calibration(path); });
  EXPECT_EQ(e2.rfind(path.string() + ": line 3: ", 0), 0u) << e2;

  // A truncated real file: the line is where the text ends.
  calibrate::save_calibration(sample(), path);
  std::string text = slurp(path);
  text.resize(text.size() / 2);
  std::ofstream(path, std::ios::trunc) << text;
  const auto lines = std::count(text.begin(), text.end(), '\n') + 1;
  const std::string e3 = error_of([&] { calibrate::load_calibration(path); });
  EXPECT_EQ(e3.rfind(path.string() + ": line " + std::to_string(lines) + ": ", 0), 0u) << e3;

  EXPECT_EQ(error_of([&] { calibrate::load_calibration(t.path() / "missing.json"); }),
            (t.path() / "missing.json").string() + ": cannot read (missing or not readable)");
}

TEST(CalibrationFile, WrongTypeNamesTheField) {
  nlohmann::json j = calibrate::to_json(sample());
  j["metrics"]["test"]["rmse_stator_k"] = "0.5";
  EXPECT_EQ(error_for(j), "cal.json: field 'metrics.test.rmse_stator_k': expected a number");

  j = calibrate::to_json(sample());
  j["metrics"]["train"]["cycles"][0].erase("samples_stator");
  EXPECT_EQ(error_for(j), "cal.json: field 'metrics.train.cycles[0].samples_stator': missing");

  j = calibrate::to_json(sample());
  j["parameters"][3]["calibrated"] = 1;
  EXPECT_EQ(error_for(j), "cal.json: field 'parameters[3].calibrated': expected true or false");

  j = calibrate::to_json(sample());
  j["data"]["files"][1]["sha256"] = nullptr;
  EXPECT_EQ(error_for(j), "cal.json: field 'data.files[1].sha256': expected a string");

  j = calibrate::to_json(sample());
  j["parameters"][0]["value"] = nullptr;  // only std_error may be null
  EXPECT_EQ(error_for(j), "cal.json: field 'parameters[0].value': expected a number");

  EXPECT_EQ(error_for(nlohmann::json::array()), "cal.json: not a calibration file (expected a JSON object)");
}

TEST(CalibrationFile, OtherVersionIsRefused) {
  nlohmann::json j = calibrate::to_json(sample());
  j.erase("parameters");  // the version is checked before anything else
  j["format_version"] = calibrate::kCalibrationFormatVersion + 1;
  EXPECT_EQ(error_for(j), "cal.json: field 'format_version': version 4, this lptn reads 1 to 3");
  j["format_version"] = 0;
  EXPECT_EQ(error_for(j), "cal.json: field 'format_version': version 0, this lptn reads 1 to 3");
}

// calibration.json before format 3: the motor as its TOML text alone.
nlohmann::json with_motor_as_text(nlohmann::json j, const std::string& text, int version) {
  j["format_version"] = version;
  j["motor"] = {{"name", j["motor"]["name"]}, {"file", j["motor"]["file"]}, {"text", text}};
  return j;
}

// Format 2's files (every calibration.json until format 3) still read: the motor parsed from its
// text, to the same constants, settings and effects as the structured copy.
TEST(CalibrationFile, VersionTwoReadsTheMotorText) {
  calibrate::CalibrationResult a = sample();
  a.motor.text = model::format_motor_file(a.motor);
  const calibrate::CalibrationResult b = calibrate::calibration_from_json(with_motor_as_text(calibrate::to_json(a), a.motor.text, 2), "old.json");
  EXPECT_EQ(b.format_version, 2);
  EXPECT_EQ(b.status, a.status);
  EXPECT_EQ(model::format_motor_file(b.motor), a.motor.text);
  EXPECT_EQ(b.motor.effects, a.motor.effects);
  EXPECT_EQ(b.motor.path, a.motor.path);
  EXPECT_EQ(b.motor.text, a.motor.text);
  EXPECT_GT(b.motor.constants.rated_power_w, 0.0);

  // A text that is no motor file: one line naming the field, the text's line and key.
  std::string bad = a.motor.text;
  bad.replace(bad.find("pole_pairs = 2"), 14, "pole_pairs = \"two\"");
  EXPECT_EQ(error_for(with_motor_as_text(calibrate::to_json(a), bad, 2)),
            "cal.json: field 'motor.text': line 5: key 'nameplate.pole_pairs': must be a finite number");
}

// The structured motor is read by the motor file's rules: a hand-edited value is refused with the
// field that holds it.
TEST(CalibrationFile, MotorFieldsAreCheckedAsInTheMotorFile) {
  const nlohmann::json good = calibrate::to_json(sample());
  EXPECT_EQ(good["motor"]["constants"]["nameplate"]["pole_pairs"], 2);
  EXPECT_EQ(good["motor"]["constants"]["losses"]["harmonic_frequency_hz"].size(), 5u);
  EXPECT_EQ(good["motor"]["parameters"]["lambda_1s"]["initial"], 40.0);
  EXPECT_EQ(good["motor"]["effects"], nlohmann::json({"airgap"}));

  nlohmann::json j = good;
  j["motor"]["constants"]["thermal"]["capacitance_rotor_core_j_per_k"] = -1.0;
  EXPECT_EQ(error_for(j), "cal.json: field 'motor.constants.thermal.capacitance_rotor_core_j_per_k': must be greater than zero");

  j = good;
  j["motor"]["constants"]["thermal"].erase("nominal_airflow_m3s");
  EXPECT_EQ(error_for(j), "cal.json: field 'motor.constants.thermal.nominal_airflow_m3s': missing");

  j = good;
  j["motor"]["constants"]["thermal"]["nominal_airflow"] = 1.0;
  EXPECT_EQ(error_for(j), "cal.json: field 'motor.constants.thermal.nominal_airflow': unknown key");

  j = good;
  j["motor"]["constants"]["nameplate"]["pole_pairs"] = 2.5;
  EXPECT_EQ(error_for(j), "cal.json: field 'motor.constants.nameplate.pole_pairs': expected a whole number");

  j = good;
  j["motor"]["constants"]["losses"]["harmonic_frequency_hz"][2] = 5.0;
  EXPECT_EQ(error_for(j), "cal.json: field 'motor.constants.losses.harmonic_frequency_hz[2]': must increase strictly");

  j = good;
  j["motor"]["constants"]["losses"]["harmonic_loss_w"].erase(1);
  EXPECT_EQ(error_for(j), "cal.json: field 'motor.constants.losses.harmonic_loss_w': must have as many entries as "
                          "motor.constants.losses.harmonic_frequency_hz");

  j = good;
  j["motor"]["parameters"]["lambda_2s"]["min"] = 3000.0;
  EXPECT_EQ(error_for(j), "cal.json: field 'motor.parameters.lambda_2s.max': must be greater than min (bounds swapped?)");

  j = good;
  j["motor"]["parameters"]["lambda_9"] = good["motor"]["parameters"]["lambda_1s"];
  EXPECT_EQ(error_for(j), "cal.json: field 'motor.parameters.lambda_9': unknown parameter");

  j = good;
  j["motor"]["effects"][0] = "windage_x";
  EXPECT_EQ(error_for(j), "cal.json: field 'motor.effects[0]': unknown effect 'windage_x'");
}

// A file of the format before outcomes were judged is read, but never as "ok": its parameters
// marked calibrated may be a motor file's guesses.
TEST(CalibrationFile, VersionOneIsReadAsUnchecked) {
  calibrate::CalibrationResult a = sample();
  nlohmann::json j = with_motor_as_text(calibrate::to_json(a), model::format_motor_file(a.motor), 1);
  j.erase("status");
  j.erase("warnings");
  for (auto& p : j["parameters"]) {
    p.erase("identifiable");
    p.erase("identifiability");
  }
  const calibrate::CalibrationResult r = calibrate::calibration_from_json(j, "old.json");
  EXPECT_EQ(r.status, calibrate::kStatusUnchecked);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0].code, "unchecked");
  EXPECT_TRUE(r.parameters[0].identifiable);
}

// Status, warnings and identifiability survive a round trip; an unknown status is refused.
TEST(CalibrationFile, OutcomeRoundTrips) {
  calibrate::CalibrationResult a = sample();
  a.status = calibrate::kStatusWarnings;
  a.warnings.push_back({"not_identifiable", "lambda_1r is not identifiable", {"lambda_1r"}});
  a.parameters[3].calibrated = false;
  a.parameters[3].identifiable = false;
  a.parameters[3].identifiability = "no rotor readings";
  const calibrate::CalibrationResult b = calibrate::calibration_from_json(calibrate::to_json(a), "cal.json");
  EXPECT_EQ(b.status, calibrate::kStatusWarnings);
  ASSERT_EQ(b.warnings.size(), 1u);
  EXPECT_EQ(b.warnings[0].code, "not_identifiable");
  EXPECT_EQ(b.warnings[0].parameters, std::vector<std::string>{"lambda_1r"});
  EXPECT_FALSE(b.parameters[3].identifiable);
  EXPECT_EQ(b.parameters[3].identifiability, "no rotor readings");
  nlohmann::json j = calibrate::to_json(a);
  j["status"] = "fine";
  EXPECT_EQ(error_for(j), "cal.json: field 'status': 'fine', expected ok, warnings or failed");
}

TEST(CalibrationFile, UnknownNamesAreRefused) {
  nlohmann::json j = calibrate::to_json(sample());
  j["parameters"][2]["name"] = "lambda_99";
  EXPECT_EQ(error_for(j), "cal.json: field 'parameters[2].name': unknown parameter 'lambda_99'");

  j = calibrate::to_json(sample());
  j["effects"][1] = "flux_capacitor";
  EXPECT_EQ(error_for(j), "cal.json: field 'effects[1]': unknown effect 'flux_capacitor'");

  j = calibrate::to_json(sample());
  j["correlated"][1]["b"] = "k_nope";
  EXPECT_EQ(error_for(j), "cal.json: field 'correlated[1].b': unknown parameter 'k_nope'");

  j = calibrate::to_json(sample());
  j["actor"]["param_names"][0] = "k_nope";
  EXPECT_EQ(error_for(j), "cal.json: field 'actor.param_names[0]': unknown parameter 'k_nope'");

  j = calibrate::to_json(sample());
  j["parameters"].erase(4);
  EXPECT_NE(error_for(j).find("cal.json: field 'parameters': 'lambda_2r' is missing"), std::string::npos);

  j = calibrate::to_json(sample());
  j["parameters"][1]["name"] = "lambda_1s";
  EXPECT_EQ(error_for(j), "cal.json: field 'parameters[1].name': 'lambda_1s' appears twice");

  j = calibrate::to_json(sample());
  j["parameters"][0]["unit"] = "W";
  EXPECT_EQ(error_for(j), "cal.json: field 'parameters[0].unit': 'W', but this lptn has lambda_1s in 'W/K'");
}

// A file written before an effect was appended to the library lacks that effect's parameters; it
// stays readable as long as it does not enable the effect (docs/effects.md, "Writing a new effect").
TEST(CalibrationFile, ParametersOfEffectsItDoesNotEnableMayBeAbsent) {
  const calibrate::CalibrationResult sample = calibrate::sample();
  int absent_effect = kNumEffects - 1;  // the last effect the sample leaves off
  while (absent_effect >= 0 && (sample.effects & effect_bit(absent_effect))) --absent_effect;
  ASSERT_GE(absent_effect, 0);
  const int p = kNumPaperParams + EffectLibrary::kParamOffsets[absent_effect];
  nlohmann::json j = calibrate::to_json(sample);
  j["parameters"].erase(static_cast<std::size_t>(p));
  const calibrate::CalibrationResult r = calibrate::calibration_from_json(j, "cal.json");
  EXPECT_EQ(r.parameters[p].name, param_spec(p).name);
  EXPECT_EQ(r.parameters[p].value, param_spec(p).initial);
  EXPECT_FALSE(r.parameters[p].calibrated);
  for (int i = 0; i < kNumParams; ++i) {
    if (i != p) {
      EXPECT_EQ(r.parameters[i].value, sample.parameters[i].value) << param_spec(i).name;
    }
  }

  // Not so for an effect the file enables.
  j = calibrate::to_json(sample);
  j["effects"].push_back(std::string(EffectLibrary::kNames[absent_effect]));
  j["parameters"].erase(static_cast<std::size_t>(p));
  // Built by appending: GCC 12's -Wrestrict misfires on "'" + std::string(...) here.
  std::string missing = "'";
  missing.append(param_spec(p).name).append("' is missing");
  EXPECT_NE(error_for(j).find(missing), std::string::npos) << error_for(j);
}

TEST(CalibrationFile, InconsistentActorIsRefused) {
  nlohmann::json j = calibrate::to_json(sample());
  j["actor"]["layers"][1]["weight"].erase(0);
  EXPECT_EQ(error_for(j), "cal.json: field 'actor.layers[1].weight': 8 numbers, expected in x out = 9");

  j = calibrate::to_json(sample());
  j["actor"]["layers"][1]["in"] = 4;
  EXPECT_EQ(error_for(j), "cal.json: field 'actor.layers[1].in': 4, but the layer before gives 3");

  j = calibrate::to_json(sample());
  j["actor"]["param_indices"][1] = 3;
  EXPECT_EQ(error_for(j), "cal.json: field 'actor.param_indices[1]': 3, but param_names[1] 'airgap_lambda' is parameter " +
                              std::to_string(param_index("airgap_lambda")));

  j = calibrate::to_json(sample());
  j["actor"]["check_actions"].erase(0);
  EXPECT_EQ(error_for(j), "cal.json: field 'actor.check_actions': 3 numbers, expected 2 checks x 2 outputs");
}

}  // namespace
}  // namespace lptn::calibrate
