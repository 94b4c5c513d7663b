// What diagnose recommends: at most one candidate per round, significant and distinguishable, and
// never one whose refit raises the held-out cycles' error (it learned the training cycles, not
// the physics), however significant; the JSON says which, with the error before and after.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>

#include "lptn_testing/small_fleet.hpp"
#include "lptn_testing/sound_candidates.hpp"
#include "trainer/diagnose/diagnose.hpp"
#include "trainer/diagnose/internal/heat_path.hpp"

namespace lptn::diagnose {
namespace {

diagnose::Candidate candidate(const char* name, diagnose::Verdict v, double test_after) {
  diagnose::Candidate c;
  c.name = name;
  c.effect = effect_index(name);
  c.verdict = v;
  c.test_rmse_k_after = test_after;
  return c;
}

TEST(Recommendation, NeverOneThatRaisesTheHeldOutError) {
  diagnose::Diagnosis d;
  d.test_rmse_k = 2.97;
  d.candidates = {candidate("rotor_speed_convection", diagnose::Verdict::significant, 3.38),  // the case
                  candidate("airgap", diagnose::Verdict::not_significant, 2.0),
                  candidate("windage", diagnose::Verdict::significant, 1.10),
                  candidate("sensor_lag", diagnose::Verdict::significant, 0.90)};
  EXPECT_TRUE(d.raises_held_out_error(d.candidates[0]));
  ASSERT_NE(d.best(), nullptr);
  EXPECT_EQ(d.best()->name, "windage") << "the first significant one that lowers the held-out error";

  const nlohmann::json j = diagnose::to_json(d);
  int recommended = 0;
  for (const auto& c : j.at("candidates")) {
    EXPECT_EQ(c.at("kind"), "library");
    EXPECT_DOUBLE_EQ(c.at("test_rmse_k_before").get<double>(), 2.97);
    recommended += c.at("recommended").get<bool>() ? 1 : 0;
  }
  EXPECT_EQ(recommended, 1);
  EXPECT_TRUE(j.at("candidates")[2].at("recommended").get<bool>());
  EXPECT_FALSE(j.at("candidates")[0].at("recommended").get<bool>());

  d.candidates.erase(d.candidates.begin() + 2, d.candidates.end());  // only the one that raises it is left
  EXPECT_EQ(d.best(), nullptr);
}

TEST(Recommendation, WithoutTestCyclesTheTrainingEvidenceDecides) {
  diagnose::Diagnosis d;
  d.test_rmse_k = std::nan("");
  d.candidates = {candidate("windage", diagnose::Verdict::significant, std::nan(""))};
  ASSERT_NE(d.best(), nullptr);
  EXPECT_FALSE(d.raises_held_out_error(d.candidates[0]));
}

// The effect's size (its first parameter) as the refit left it.
void set_size(diagnose::Candidate& c, double value, double std_error) {
  const int i = kNumPaperParams + EffectLibrary::kParamOffsets[static_cast<std::size_t>(c.effect)];
  c.refit.values[i] = value;
  c.refit.std_error[i] = std_error;
}

const nlohmann::json& listed(const nlohmann::json& j, const std::string& name) {
  for (const auto& c : j.at("candidates"))
    if (c.at("effect") == name) return c;
  throw std::runtime_error(name + " not listed");
}

// The sensor fault: a term significant at 262 +- 193 W. Not pinned (the error is more than
// half the value), so not recommended, and the reason says so; the next one, pinned, is.
TEST(Recommendation, OnlyWhereTheSizeIsPinnedAndTheReasonSaysWhyNot) {
  diagnose::Diagnosis d;
  d.test_rmse_k = 0.907;
  d.candidates = {candidate("heat_stator_core_speed", diagnose::Verdict::significant, 0.877),
                  candidate("heat_stator_winding_i2f", diagnose::Verdict::significant, 0.60),
                  candidate("windage", diagnose::Verdict::significant, 0.70)};
  set_size(d.candidates[0], 262, 193);
  set_size(d.candidates[1], 1190, 0.5 * 1190 + 1);  // just beyond half its value
  set_size(d.candidates[2], 300, 0.5 * 300);         // exactly half: pinned
  EXPECT_FALSE(diagnose::pinned(d.candidates[0]));
  EXPECT_FALSE(diagnose::pinned(d.candidates[1]));
  EXPECT_TRUE(diagnose::pinned(d.candidates[2]));
  ASSERT_NE(d.best(), nullptr);
  EXPECT_EQ(d.best()->name, "windage");
  const std::string why = d.not_recommended_because(d.candidates[0]);
  EXPECT_NE(why.find("not pinned"), std::string::npos) << why;
  EXPECT_NE(why.find("heat_stator_core_speed_w = 262 +- 1.9e+02 W"), std::string::npos) << why;

  const nlohmann::json j = diagnose::to_json(d);
  EXPECT_EQ(listed(j, "heat_stator_core_speed").at("reason"), why);
  EXPECT_FALSE(listed(j, "heat_stator_core_speed").at("pinned").get<bool>());
  EXPECT_TRUE(listed(j, "windage").at("recommended").get<bool>());
  EXPECT_EQ(listed(j, "windage").at("reason"), "");

  // No standard error at all is not pinned either.
  set_size(d.candidates[2], 300, std::nan(""));
  EXPECT_EQ(d.best(), nullptr);
  EXPECT_NE(d.not_recommended_because(d.candidates[2]).find("no standard error"), std::string::npos);
}

// The held-out error must fall: a candidate that leaves it where it was is not recommended.
TEST(Recommendation, NeedsTheHeldOutErrorToFall) {
  diagnose::Diagnosis d;
  d.test_rmse_k = 1.0;
  d.candidates = {candidate("windage", diagnose::Verdict::significant, 1.0),
                  candidate("airgap", diagnose::Verdict::significant, 0.8)};
  set_size(d.candidates[0], 300, 10);
  set_size(d.candidates[1], 50, 5);
  ASSERT_NE(d.best(), nullptr);
  EXPECT_EQ(d.best()->name, "airgap");
  EXPECT_NE(d.not_recommended_because(d.candidates[0]).find("does not lower the held-out error"), std::string::npos);
  // A significant candidate with nothing against it but a better one ahead says so.
  d.candidates[0].test_rmse_k_after = 0.9;
  d.candidates[0].verdict = diagnose::Verdict::significant;
  std::swap(d.candidates[0], d.candidates[1]);
  EXPECT_EQ(listed(diagnose::to_json(d), "windage").at("reason"), "ranked after airgap (one recommendation per diagnosis)");
}

// A refit that ended above its baseline from every start is listed as failed, with why, and is
// neither significant nor recommended, wherever it stands in the list.
TEST(Recommendation, AFailedRefitIsListedNotJudged) {
  diagnose::Diagnosis d;
  d.rmse_k = 1.348;
  d.test_rmse_k = 1.0;
  diagnose::Candidate failed = candidate("heat_stator_core_power", diagnose::Verdict::refit_failed, std::nan(""));
  failed.refit_rmse_k = 2.417;
  failed.reason = "the refit ends above the baseline's 1.348 K from every start";
  set_size(failed, 400, 1);
  d.candidates = {failed};
  EXPECT_EQ(d.best(), nullptr);
  const nlohmann::json c = diagnose::to_json(d).at("candidates").at(0);
  EXPECT_EQ(c.at("verdict"), "refit failed");
  EXPECT_FALSE(c.at("significant").get<bool>());
  EXPECT_FALSE(c.at("recommended").get<bool>());
  EXPECT_TRUE(c.at("test_rmse_k_after").is_null());
  EXPECT_EQ(c.at("reason"), failed.reason);
}

// An effect whose neutral value lies beyond the motor file's bound cannot be switched off by its
// refit: a sensor lag of at least 5 s on data whose sensor does not lag ends above the baseline
// from every start, and that is the data pulling it towards nothing, not a lost fit: judged at the
// baseline, not significant, where diagnose listed "refit failed" (the clean 48 h bench dump's
// sensor lag at its 0.5 s floor, before).
TEST(Recommendation, AnEffectHeldAtTheBoundBeforeItsNeutralValueIsNotSignificant) {
  const auto g = testing::generate({}, 4, 20, 25, 13);
  model::MotorFile motor = g->motor;
  const int tau = param_index("sensor_time_constant_s");
  // As a motor file's [parameters.sensor_time_constant_s] sets it (one enable_effect keeps).
  model::ParameterSetting& setting = motor.parameters[static_cast<std::size_t>(tau)];
  setting.min = 5.0;
  setting.initial = std::max(setting.initial, 5.0);
  setting.in_file = true;
  diagnose::Settings settings;
  settings.threads = 2;
  const diagnose::Diagnosis d = diagnose::diagnose(motor, g->calibrated.values, g->dataset, g->split, settings);
  const diagnose::Candidate* lag = nullptr;
  for (const diagnose::Candidate& c : d.candidates)
    if (c.name == "sensor_lag") lag = &c;
  ASSERT_NE(lag, nullptr);
  std::printf("sensor_lag: %s, %s; LR %.2f\n", diagnose::to_string(lag->verdict), lag->reason.c_str(), lag->statistic);
  EXPECT_EQ(lag->verdict, diagnose::Verdict::not_significant);
  EXPECT_NE(lag->reason.find("past the motor file's bound sensor_time_constant_s = 5 s"), std::string::npos) << lag->reason;
  EXPECT_EQ(lag->refit_rmse_k, d.rmse_k);
  EXPECT_EQ(lag->statistic, 0.0);
  EXPECT_NEAR(lag->refit.values[tau], 5.0, 1e-5);
  diagnose::expect_sound_candidates(d, "sensor lag floored at 5 s");
}

// "Not distinguishable" names only a parameter that shares a heat path with the candidate: a
// stator term and a rotor conductance have none while the model leaves the sides unconnected.
TEST(Recommendation, ConfoundingNeedsAHeatPath) {
  using diagnose::internal::shares_heat_path;
  const int stator_term = effect_index("heat_stator_core_speed"), rotor_term = effect_index("heat_rotor_core_i2f");
  EXPECT_FALSE(shares_heat_path(kLambda1r, stator_term, effect_bit(stator_term)));
  EXPECT_TRUE(shares_heat_path(kLambda2s, stator_term, effect_bit(stator_term)));
  EXPECT_TRUE(shares_heat_path(kKPfe, stator_term, effect_bit(stator_term)));  // splits the iron loss between the sides
  EXPECT_TRUE(shares_heat_path(kLambda1r, rotor_term, effect_bit(rotor_term)));
  EXPECT_FALSE(shares_heat_path(kLambda12s, effect_index("windage"), effect_bit(effect_index("windage"))));
  // Once the model links the sides, every parameter shares a path.
  const EffectSet linked = effect_bit(stator_term) | effect_bit(effect_index("airgap"));
  EXPECT_TRUE(shares_heat_path(kLambda1r, stator_term, linked));
  const int path = effect_index("path_stator_winding_rotor_winding");
  EXPECT_TRUE(shares_heat_path(kLambda1r, path, effect_bit(path)));
}

}  // namespace
}  // namespace lptn::diagnose
