// TD3 calibration on generated data: it learns with a small budget, a killed run resumes to the
// same result, and the shipped config file is the built-in defaults.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "lptn_testing/fleet_dump.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/td3/td3_calibration.hpp"

namespace lptn::td3 {
namespace {

// Four cycles of 20-25 minutes, one held out (the search suite's dump).
const testing::Dump& generated() {
  static const testing::Dump* d = [] {
    auto* x = new testing::Dump;
    testing::generate_dump(*x, 4, 11, 1200, 1500, 0.25);
    return x;
  }();
  return *d;
}

// A budget that runs in seconds: smaller networks and episodes than the paper's.
TrainingSettings small(Formulation f, int episodes) {
  TrainingSettings s = default_settings(f);
  s.max_episodes = episodes;
  s.max_steps_per_episode = 3000;
  s.agent.hidden = 64;
  s.updates_per_episode = f == Formulation::per_step ? 60 : 40;
  s.random_episodes = f == Formulation::per_step ? 3 : 15;
  s.checkpoint_every = 5;
  if (f == Formulation::sequential) {
    s.agent.hidden = 64;
    s.random_episodes = 5;
    s.sequential.environments = 4;
  }
  return s;
}

double average(const std::vector<EpisodeRecord>& curve, std::size_t from, std::size_t to) {
  double sum = 0;
  for (std::size_t i = from; i < to; ++i) sum += curve[i].reward;
  return sum / static_cast<double>(to - from);
}

// One seed's run of a formulation with a small budget: its result fits the held-out cycle better
// than the guess, the budget is counted, and (but for the per-step formulation) the training
// episodes' return rises. `initial` and `last`: the deterministic policy's evaluation reward
// before training and at the last checkpoint, for the caller to judge.
void expect_learns_on_seed(Formulation f, int episodes, int random, std::uint64_t seed, double& initial, double& last) {
  const testing::Dump& d = generated();
  testing::TempDir checkpoints;
  TrainingSettings s = small(f, episodes);
  s.seed = seed;
  const Td3Outcome o = train_td3(d.motor, d.dataset, d.split.train, s, checkpoints.path(), false);
  ASSERT_EQ(o.curve.size(), static_cast<std::size_t>(episodes));
  const Model<double> model = d.motor.model();
  const calibrate::SplitMetrics before = calibrate::evaluate_split(model, d.motor.initial_values(), d.dataset, d.split.test);
  const calibrate::SplitMetrics after = calibrate::evaluate_split(model, o.values, d.dataset, d.split.test);
  // The deterministic policy's reward on fixed windows (evaluated at every checkpoint) rises from
  // the untrained policy's; so does the training episodes' own average where windows vary less.
  double last_evaluation = std::nan("");
  for (const EpisodeRecord& r : o.curve)
    if (!std::isnan(r.evaluation)) last_evaluation = r.evaluation;
  const std::size_t n = o.curve.size(), q = (n - static_cast<std::size_t>(random)) / 3;
  const double early = average(o.curve, static_cast<std::size_t>(random), static_cast<std::size_t>(random) + q);
  const double late = average(o.curve, n - q, n);
  std::printf("%s, seed %d: evaluation reward %.4f -> %.4f, episode reward %.4f -> %.4f; test stator RMSE %.2f K -> %.2f K (%.1f s)\n",
              to_string(f), static_cast<int>(seed), o.initial_evaluation, last_evaluation, early, late, before.stator.rmse_k,
              after.stator.rmse_k, o.seconds);
  initial = o.initial_evaluation;
  last = last_evaluation;
  if (f != Formulation::per_step) {
    EXPECT_GT(late, early);
  }
  EXPECT_LT(after.stator.rmse_k, before.stator.rmse_k);
  // The budget is counted: at least every training cycle once per episode, one update per step asked.
  std::size_t train_steps = 0;
  for (std::size_t c : d.split.train) train_steps += d.dataset.cycles[c].steps;
  EXPECT_GT(o.simulated_steps, train_steps);
  EXPECT_GT(o.updates, 0);
}

// The deterministic policy's evaluation reward at the last checkpoint beats the untrained one's.
void expect_learns(Formulation f, int episodes, int random) {
  double initial = 0, last = 0;
  expect_learns_on_seed(f, episodes, random, 1, initial, last);
  EXPECT_GT(last, initial);
}

// The sequential formulation: the actor's rollouts fall further in ln RMSE than the untrained
// actor's, the episodes' own return rises, and the result (the best set the rollouts visit, on
// the data's grid) fits unseen cycles far better than the guess, and as well as the best set scored.
TEST(Td3Calibration, SequentialFormulationLearnsWithASmallBudget) {
  expect_learns(Formulation::sequential, 60, 5);
  const testing::Dump& d = generated();
  testing::TempDir checkpoints;
  const Td3Outcome o = train_td3(d.motor, d.dataset, d.split.train, small(Formulation::sequential, 20), checkpoints.path(), false);
  const calibrate::SplitMetrics train = calibrate::evaluate_split(d.motor.model(), o.values, d.dataset, d.split.train);
  EXPECT_NEAR(o.best_train_rmse_k, model::pool({train.stator, train.rotor}).rmse_k, 1e-9) << "the result is scored as the metrics score it";
  EXPECT_GT(o.simulated_steps, 0u);
  EXPECT_GT(o.updates, 0);
}

// A warm start takes the earlier agent's networks: its first rollouts are the earlier agent's last
// (the same data here), and it takes no random rounds. Another agent shape is refused.
TEST(Td3Calibration, AWarmStartContinuesFromTheEarlierAgent) {
  const testing::Dump& d = generated();
  testing::TempDir first_dir, warm_dir, other_dir;
  const TrainingSettings s = small(Formulation::sequential, 10);
  const Td3Outcome first = train_td3(d.motor, d.dataset, d.split.train, s, first_dir.path(), false);
  ASSERT_TRUE(std::filesystem::exists(first.agent_file));
  const WarmStart warm{first.agent_file, "sha"};
  const Td3Outcome again = train_td3(d.motor, d.dataset, d.split.train, s, warm_dir.path(), false, {}, warm);
  EXPECT_EQ(again.initial_evaluation, first.curve.back().evaluation);
  const Td3Outcome cold = train_td3(d.motor, d.dataset, d.split.train, s, other_dir.path(), false);
  EXPECT_NE(cold.initial_evaluation, again.initial_evaluation);
  TrainingSettings other = s;
  other.agent.hidden = 32;
  EXPECT_THROW(train_td3(d.motor, d.dataset, d.split.train, other, other_dir.path(), false, {}, warm), std::runtime_error);
  EXPECT_THROW(train_td3(d.motor, d.dataset, d.split.train, small(Formulation::per_step, 2), other_dir.path(), false, {}, warm),
               std::runtime_error);
}

// The paper's actor scheduled over cycles: with an untrained actor held at one set, scheduling
// gives exactly the constant set's figures; a trained one gives its own.
TEST(Td3Calibration, TheScheduledActorIsScoredOnTheCyclesGiven) {
  const testing::Dump& d = generated();
  testing::TempDir dir;
  const Td3Outcome o = train_td3(d.motor, d.dataset, d.split.train, small(Formulation::per_step, 4), dir.path(), false);
  Td3Outcome flat = o;  // an actor whose every output is the constant set: zero weights, biases atanh(u)
  std::fill(flat.actor.w3.begin(), flat.actor.w3.end(), 0.0f);
  const calibrate::FreeParameters free = calibrate::FreeParameters::from_motor(d.motor);
  for (std::size_t j = 0; j < free.size(); ++j)
    flat.actor.b3[j] = static_cast<float>(std::atanh(to_normalized(o.values[free.index[j]], free.min[j], free.max[j])));
  const Model<double> model = d.motor.model();
  const calibrate::SplitMetrics constant = calibrate::evaluate_split(model, o.values, d.dataset, d.split.test);
  const calibrate::SplitMetrics held = evaluate_scheduled_actor(flat, d.motor, d.dataset, d.split.test);
  EXPECT_NEAR(held.stator.rmse_k, constant.stator.rmse_k, 1e-3 * constant.stator.rmse_k);
  const calibrate::SplitMetrics scheduled = evaluate_scheduled_actor(o, d.motor, d.dataset, d.split.test);
  EXPECT_NE(scheduled.stator.rmse_k, constant.stator.rmse_k);
  EXPECT_EQ(scheduled.cycles.size(), d.split.test.size());
}

// The paper's per-step formulation at this budget learns on most seeds, not on every one: its last
// checkpoint's evaluation is one noisy sample of a policy still moving, and which way seed 1's goes
// depends on the BLAS kernel's rounding (0.367 -> 0.605 with OpenBLAS's SkylakeX kernel, 0.367 ->
// 0.294 with its Haswell kernel on the same machine, while the result's test error fell from 3.5
// to 0.3 K). So over five seeds: the mean evaluation reward at the last checkpoint beats the
// untrained policy's, and at least three of the five rise (five of five and four of five on
// those two kernels).
TEST(Td3Calibration, PaperFormulationLearnsWithASmallBudget) {
  double initial_sum = 0, last_sum = 0;
  int rose = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    double initial = 0, last = 0;
    expect_learns_on_seed(Formulation::per_step, 30, 3, seed, initial, last);
    initial_sum += initial;
    last_sum += last;
    rose += last > initial ? 1 : 0;
  }
  EXPECT_GT(last_sum, initial_sum);
  EXPECT_GE(rose, 3);
}

TEST(Td3Calibration, EpisodeFormulationLearnsWithASmallBudget) { expect_learns(Formulation::episode, 150, 15); }

class Td3Resume : public ::testing::TestWithParam<Formulation> {};
INSTANTIATE_TEST_SUITE_P(Formulations, Td3Resume,
                         ::testing::Values(Formulation::sequential, Formulation::per_step, Formulation::episode),
                         [](const ::testing::TestParamInfo<Formulation>& i) {
                           std::string n = to_string(i.param);
                           std::erase(n, '-');
                           return n;
                         });

TEST_P(Td3Resume, AKilledRunResumesToTheSameResult) {
  const testing::Dump& d = generated();
  TrainingSettings s = small(GetParam(), 7);
  s.max_steps_per_episode = 400;
  s.agent.hidden = 16;
  s.updates_per_episode = 10;
  s.random_episodes = 2;
  s.checkpoint_every = 2;
  s.sequential.environments = 2;
  s.sequential.steps_per_episode = 3;
  testing::TempDir straight_dir, killed_dir;
  const Td3Outcome straight = train_td3(d.motor, d.dataset, d.split.train, s, straight_dir.path(), false);
  // Killed in episode 6: the last checkpoint is after episode 4; episodes 5 and 6 are lost.
  const Td3Outcome killed = train_td3(d.motor, d.dataset, d.split.train, s, killed_dir.path(), false,
                                      [](const EpisodeReport& r) { return r.episode < 5; });
  EXPECT_FALSE(killed.completed);
  const Td3Outcome resumed = train_td3(d.motor, d.dataset, d.split.train, s, killed_dir.path(), true);
  EXPECT_EQ(resumed.resumed_from, 4);
  ASSERT_EQ(resumed.curve.size(), straight.curve.size());
  for (std::size_t i = 0; i < straight.curve.size(); ++i) {
    EXPECT_EQ(resumed.curve[i].cycle, straight.curve[i].cycle) << i;
    EXPECT_EQ(resumed.curve[i].reward, straight.curve[i].reward) << i;
  }
  for (int i = 0; i < kNumParams; ++i) EXPECT_EQ(resumed.values[i], straight.values[i]) << param_spec(i).name;
  EXPECT_EQ(resumed.actor.w3, straight.actor.w3);
  // Other settings cannot continue this checkpoint.
  s.agent.tau = 0.01;
  EXPECT_THROW(train_td3(d.motor, d.dataset, d.split.train, s, killed_dir.path(), true), std::runtime_error);
}

TEST(Td3Settings, ShippedConfigFilesAreTheBuiltInDefaults) {
  const auto docs = std::filesystem::path(LPTN_SOURCE_DIR) / "docs";
  EXPECT_EQ(to_json(load_settings(docs / "td3.toml", Formulation::sequential)), to_json(default_settings(Formulation::sequential)));
  EXPECT_EQ(to_json(load_settings(docs / "td3-paper.toml", Formulation::per_step)), to_json(default_settings(Formulation::per_step)));
  // The paper's file is no place for the sequential formulation's table.
  EXPECT_THROW(load_settings(docs / "td3.toml", Formulation::per_step), SettingsError);
}

TEST(Td3Settings, MethodNamesRoundTrip) {
  for (Formulation f : {Formulation::sequential, Formulation::per_step, Formulation::episode})
    EXPECT_EQ(formulation_from_method(to_string(f)), f);
  EXPECT_STREQ(to_string(Formulation::sequential), "td3");
  EXPECT_STREQ(to_string(Formulation::per_step), "td3-paper");
  EXPECT_THROW(formulation_from_method("td4"), std::invalid_argument);
}

TEST(Td3Settings, BadKeysAndValuesNameTheFileLineAndKey) {
  testing::TempDir dir;
  const auto file = dir.path() / "bad.toml";
  auto expect_error = [&](const std::string& text, const std::string& part) {
    std::ofstream(file) << text;
    try {
      load_settings(file, Formulation::per_step);
      ADD_FAILURE() << "no error for: " << text;
    } catch (const SettingsError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expect_error("max_episodes = 10\nmax_episodez = 3\n", "bad.toml:2: key 'max_episodez': unknown key");
  expect_error("[agent]\ntau = 2.0\n", "bad.toml:2: key 'agent.tau': must lie between 0 and 1");
  expect_error("max_episodes = 1.5\n", "key 'max_episodes': must be an integer");
  expect_error("max_episodes = \n", "bad.toml:1:");
}

}  // namespace
}  // namespace lptn::td3
