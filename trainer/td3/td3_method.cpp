#include "trainer/td3/td3_method.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "hostio/atomic_file.hpp"
#include "hostio/progress_line.hpp"
#include "hostio/sha256.hpp"
#include "trainer/td3/td3_calibration.hpp"
#include "trainer/td3/td3_settings.hpp"

namespace lptn::td3 {
namespace {

// The agent a later --warm-start continues: beside the output as OUT.agent (written before the
// output, atomically), named with its hash in method.details.
void keep_agent(const calibrate::CalibrationRequest& a, const Td3Outcome& o, calibrate::CalibrationResult& r) {
  if (o.agent_file.empty()) return;
  const std::filesystem::path kept = a.out + ".agent";
  std::ifstream in(o.agent_file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw std::runtime_error(o.agent_file.string() + ": cannot read the agent to keep");
  hostio::write_file_atomically(kept, bytes);
  r.details["agent_file"] = kept.filename().string();
  r.details["agent_sha256"] = hostio::sha256_hex(bytes.data(), bytes.size());
}

// A string field of method.details, "" where absent or not a string.
std::string detail(const calibrate::CalibrationResult& r, const char* key) {
  const auto it = r.details.find(key);
  return it != r.details.end() && it->is_string() ? it->get<std::string>() : std::string();
}

// --warm-start FILE: an earlier td3 calibration of the same free parameters, its agent beside it.
// Read as every command reads a calibration (load_calibration: a file that is not one is bad input
// naming its field).
WarmStart warm_start_from(const calibrate::CalibrationRequest& a, const MotorFile& motor) {
  if (a.warm_start.empty()) return {};
  const std::filesystem::path file = a.warm_start;
  const calibrate::CalibrationResult earlier = calibrate::load_calibration(file);
  const std::string agent_file = detail(earlier, "agent_file");
  if (earlier.method != "td3" || agent_file.empty())
    throw hostio::BadInput(file.string() + ": method.details.agent_file: not a td3 calibration with an agent to start from");
  // The same free parameters and bounds: the agent's actions and states mean nothing otherwise.
  const calibrate::FreeParameters free = calibrate::FreeParameters::from_motor(motor);
  std::vector<std::string> before, now;
  for (const calibrate::ParameterResult& p : earlier.parameters)
    if (p.calibrated) before.push_back(p.name + " [" + std::to_string(p.min) + ", " + std::to_string(p.max) + "]");
  for (std::size_t k = 0; k < free.size(); ++k)
    now.push_back(std::string(param_spec(free.index[k]).name) + " [" + std::to_string(free.min[k]) + ", " + std::to_string(free.max[k]) + "]");
  if (before != now)
    throw hostio::BadInput(file.string() + ": parameters: calibrated other parameters or bounds than " + a.motor + " marks; a warm start needs the same");
  const std::filesystem::path agent = file.parent_path() / agent_file;
  if (!std::filesystem::exists(agent)) throw hostio::BadInput(file.string() + ": method.details.agent_file: " + agent.string() + " does not exist");
  const std::string sha = hostio::sha256_file(agent);
  if (sha != detail(earlier, "agent_sha256"))
    throw hostio::BadInput(file.string() + ": method.details.agent_sha256: " + agent.string() + " is not the agent this calibration wrote");
  return {agent, sha};
}

// The best set of every checkpoint scored on the test cycles, after training (never seen by it).
nlohmann::json test_curve(const MotorFile& motor, const data::Dataset& dataset, const calibrate::Split& split, const Td3Outcome& o) {
  nlohmann::json curve = nlohmann::json::array();
  const Model<double> model = motor.model();
  for (std::size_t i = 0; i < o.best_at_checkpoints.size(); ++i) {
    const calibrate::SplitMetrics m = calibrate::evaluate_split(model, o.best_at_checkpoints[i].second, dataset, split.test);
    curve.push_back({{"round", o.best_at_checkpoints[i].first}, {"seconds", o.checkpoint_seconds[i]},
                     {"test_rmse_k", pool({m.stator, m.rotor}).rmse_k}});
  }
  return curve;
}

}  // namespace

void calibrate_td3(const calibrate::CalibrationRequest& a, const MotorFile& motor, calibrate::DatasetRef shared, const calibrate::Split& split,
                   calibrate::CalibrationResult& r, const calibrate::CalibrationProgress& progress) {
  const data::Dataset& dataset = shared.data;  // TD3 runs in one process (the workflow refuses MPI for it)
  const Formulation formulation = formulation_from_method(a.method);
  TrainingSettings settings = default_settings(formulation);
  if (!a.td3_config.empty()) settings = load_settings(a.td3_config, formulation);
  if (a.td3_config.empty() || a.seed_given) settings.seed = settings.agent.seed = a.seed;  // --seed wins over the file
  if (a.episodes > 0) settings.max_episodes = a.episodes;
  bool rotor = false;
  for (std::size_t c : split.train) rotor = rotor || dataset.cycles[c].has(data::Channel::rotor_c);
  if (!rotor) settings.reward.w3 = 0.0;  // eq. 15 without the rotor term where the rotor is not measured
  const WarmStart warm = warm_start_from(a, motor);
  const std::filesystem::path checkpoints = a.checkpoint_dir.empty() ? std::filesystem::path(a.out + ".checkpoints") : std::filesystem::path(a.checkpoint_dir);
  const auto report = [&](const EpisodeReport& e) {
    if (!progress) return true;
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  formulation == Formulation::sequential
                      ? "%s: round %4d/%d %s reward %7.3f  average %7.3f  %s elapsed, ~%s left%s"
                      : "%s: episode %4d/%d %s reward %7.3f  average %7.3f  %s elapsed, ~%s left%s",
                  to_string(formulation), e.episode, e.max_episodes,
                  hostio::ProgressLine::bar(double(e.episode) / e.max_episodes).c_str(), e.reward, e.average,
                  hostio::ProgressLine::clock(e.seconds).c_str(), hostio::ProgressLine::clock(e.seconds_left).c_str(),
                  e.random ? " (random actions)" : "");
    progress(buf, e.episode == e.max_episodes);
    return true;
  };
  const Td3Outcome o = train_td3(motor, dataset, split.train, settings, checkpoints, a.resume, report, warm);
  for (int i = 0; i < kNumParams; ++i) r.parameters[static_cast<std::size_t>(i)].value = o.values[i];
  r.method = to_string(formulation);
  r.settings = to_json(settings);
  nlohmann::json curve = nlohmann::json::array();
  for (const EpisodeRecord& e : o.curve) curve.push_back(to_json(e));
  const bool sequential = formulation == Formulation::sequential;
  r.details = {{sequential ? "rounds" : "episodes", o.episodes},
               {"initial_evaluation", o.initial_evaluation},
               {"resumed_from_episode", o.resumed_from},
               {"checkpoints", checkpoints.string()},
               {"constant_set", sequential
                                    ? "the best set the deterministic actor's rollouts visited at the checkpoints (scored on the training grid, the best "
                                      "three re-scored on the data's own grid with the metrics' start offsets); round 0: the untrained actor or the guess"
                                    : "policy over the training data's operating points, tanh outputs averaged, mapped onto the bounds; "
                                      "of the checkpoints' sets the one with the lowest training RMSE (episode 0: the starting guess)"},
               {sequential ? "best_round" : "best_episode", o.best_episode},
               {"best_train_rmse_k", o.best_train_rmse_k},
               {"training_curve", curve}};
  if (!sequential) r.details["reached_target"] = o.reached_target;  // the paper's stop rule; the sequential one has none
  r.details["simulated_steps"] = o.simulated_steps;
  r.details["updates"] = o.updates;
  if (sequential) {
    r.details["warm_start"] = a.warm_start.empty() ? nlohmann::json(nullptr) : nlohmann::json{{"file", a.warm_start}, {"agent_sha256", warm.sha256}};
    keep_agent(a, o, r);
    if (a.test_curve) r.details["test_curve"] = test_curve(motor, dataset, split, o);
  }
  r.seconds = o.seconds;
  // The sequential actor steps through parameter space; it maps no operating point to a set, so
  // there is no actor to flash.
  r.has_actor = !sequential;
  if (!r.has_actor) return;
  // Does scheduling with the operating point pay on data the training never saw? (docs/benchmarks.md:
  // where the actor wins.)
  if (!split.test.empty()) {
    const calibrate::SplitMetrics scheduled = evaluate_scheduled_actor(o, motor, dataset, split.test);
    const calibrate::SplitMetrics constant = calibrate::evaluate_split(motor.model(), o.values, dataset, split.test);
    const double s = pool({scheduled.stator, scheduled.rotor}).rmse_k, c = pool({constant.stator, constant.rotor}).rmse_k;
    r.details["scheduled_actor"] = {{"test_rmse_k", s}, {"test_rmse_stator_k", scheduled.stator.rmse_k},
                                    {"test_rmse_rotor_k", scheduled.rotor.rmse_k}, {"constant_set_test_rmse_k", c},
                                    {"actor_wins", s < c},
                                    {"how", "open loop over the test cycles, the parameters the actor's at every step (the constant set where "
                                            "torque is missing), start offsets fitted for the constant set; stator and rotor pooled"}};
  }
  calibrate::ActorExport& x = r.actor;
  x.obs_offset = {0.0, 0.0};
  x.obs_scale = o.obs_scale;
  x.layers = {{o.actor.inputs, o.actor.hidden, o.actor.w1, o.actor.b1},
              {o.actor.hidden, o.actor.hidden, o.actor.w2, o.actor.b2},
              {o.actor.hidden, o.actor.outputs, o.actor.w3, o.actor.b3}};
  x.param_indices = o.param_indices;
  x.check_obs = o.check_obs;
  x.check_actions = o.check_actions;
}

}  // namespace lptn::td3
