// What diagnose recommends: at most one candidate per round, significant and distinguishable, and
// never one whose refit raises the held-out cycles' error (it learned the training cycles, not
// the physics), however significant; the JSON says which, with the error before and after.
#include <gtest/gtest.h>

#include <cmath>

#include "trainer/diagnose/diagnose.hpp"

namespace lptn {
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

}  // namespace
}  // namespace lptn
