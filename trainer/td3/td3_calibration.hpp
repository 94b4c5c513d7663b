// Calibration with TD3, three formulations (TrainingSettings::formulation). The sequential one
// (`--method td3`, internal/sequential.cpp) steps through parameter sets, rewarded with the fall
// in ln RMSE. The paper's (`td3-paper`): the parameterized model runs over a driving cycle drawn
// at random per episode; the agent observes motor speed and torque (normalized) and acts with the
// calibrated parameters (tanh, then scaled onto each parameter's bounds, log scale); eq. 15
// rewards it for every step's temperature error. `td3-episode` holds one action from the cycle's
// start to the end of a window and rewards it with that stretch's error (a contextual bandit).
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lptn/model.hpp"
#include "trainer/calibrate/metrics.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/model/motor_file.hpp"
#include "trainer/td3/td3_settings.hpp"

namespace lptn::td3 {

struct EpisodeRecord {
  int episode = 0;          // 1-based
  std::string cycle;
  double reward = 0;        // eq. 15 per agent step, averaged over the episode
  double average = 0;       // of `reward` over the last averaging_window episodes
  double mean_abs_error_k = 0;  // |Ts - T1| (+ |Tr - T3| where measured), averaged over the episode
  double seconds = 0;       // since the run started (across resumes)
  // At checkpoints: the deterministic policy's reward (no exploration) on fixed windows, the first
  // of each training cycle, as the TD3 authors evaluate; NaN between checkpoints. Episodes' own
  // rewards vary with the window drawn; this does not.
  double evaluation = std::numeric_limits<double>::quiet_NaN();
};

// One record as calibration.json's training curve and the checkpoints hold it (null evaluation
// between checkpoints), and back.
nlohmann::json to_json(const EpisodeRecord& record);
EpisodeRecord record_from_json(const nlohmann::json& j);

struct EpisodeReport {
  int episode = 0, max_episodes = 0;
  double reward = 0, average = 0;
  double seconds = 0, seconds_left = 0;
  bool random = false;  // acting at random (before learning starts)
};

// Called after every episode; returning false stops the run at once, as a kill would (tests).
using Td3Progress = std::function<bool(const EpisodeReport&)>;

// A retrain that starts from an earlier run's agent (`lptn calibrate --method td3 --warm-start`):
// its networks, with no random rounds and exploration from twice its final noise. Only the
// sequential formulation; the agent file must fit (the same free parameters).
struct WarmStart {
  std::filesystem::path agent_file;  // empty: from scratch
  std::string sha256;                // of the agent file; part of the run's identity for --resume
};

struct Td3Outcome {
  // What the paper reports: one constant parameter set. At every checkpoint the policy is
  // evaluated at the operating points of the training data (every 5 s of every training cycle for
  // the per-step formulation, each episode-length window's context for the episode one), its tanh
  // outputs averaged, and the mean mapped onto the bounds (a geometric mean for log-scaled
  // parameters). The set returned is the one of these that fit the training cycles best (the
  // starting guess if none did better: best_episode 0); the actor is the one at the end. The
  // sequential formulation returns instead the best set its actor's rollouts visited (best_episode
  // is then the round), and its actor (state -> step) is not one to flash.
  ParamVector<double> values{};
  int best_episode = 0;
  double best_train_rmse_k = 0;
  ActorWeightsPlain actor;
  std::vector<int> param_indices;       // which parameter each action drives
  std::array<double, 2> obs_scale{1, 1};  // speed_rpm, torque_nm divided by these (offset 0)
  std::vector<float> check_obs, check_actions;  // libtorch's own outputs, for exported forward passes
  std::vector<EpisodeRecord> curve;
  double initial_evaluation = 0;  // the untrained policy's evaluation reward
  int episodes = 0;
  bool reached_target = false;  // stopped because the average reward reached stop_average_reward
  bool completed = false;       // false if the progress callback stopped it
  int resumed_from = 0;         // episode the run continued after (0: fresh)
  double seconds = 0;
  // The budget spent: model steps simulated (every grid, the start offsets' fits and the sets'
  // scores included) and gradient steps taken.
  std::size_t simulated_steps = 0;
  long long updates = 0;
  // The sequential formulation: the agent as it ended (the last checkpoint's file), for a later
  // --warm-start; and at every checkpoint the best set so far, for instruments that score it.
  std::filesystem::path agent_file;
  std::vector<std::pair<int, ParamVector<double>>> best_at_checkpoints;
  std::vector<double> checkpoint_seconds;
};

// The paper's actor as it meant it: the parameters scheduled with the operating point at every
// grid step (speed and torque in, as in training; the constant set where torque is missing, as
// the firmware does), the model run open loop over each listed cycle from start offsets fitted
// for the constant set. What `--use-actor` would give against the constant set on those cycles.
// Only for the formulations whose actor maps an operating point to a set (not the sequential one).
calibrate::SplitMetrics evaluate_scheduled_actor(const Td3Outcome& outcome, const MotorFile& motor, const data::Dataset& dataset,
                                      const std::vector<std::size_t>& cycles);

// Trains on the listed cycles. Checkpoints go to `checkpoint_dir` every checkpoint_every episodes
// (agent, replay buffer, every random generator's state, the curve), written atomically; with
// `resume` the run continues after the last checkpoint there (same settings and data required,
// else std::runtime_error says what differs). Deterministic for a given settings.seed.
Td3Outcome train_td3(const MotorFile& motor, const data::Dataset& dataset, const std::vector<std::size_t>& train,
                     const TrainingSettings& settings, const std::filesystem::path& checkpoint_dir, bool resume,
                     const Td3Progress& progress = {}, const WarmStart& warm = {});

}  // namespace lptn::td3
