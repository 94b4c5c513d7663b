#include "trainer/td3/td3_calibration.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "hostio/worker_threads.hpp"
#include "lptn/actor.hpp"
#include "trainer/model/initial_offsets.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/model/simulate.hpp"
#include "trainer/td3/internal/checkpoint.hpp"
#include "trainer/td3/internal/run_record.hpp"
#include "trainer/td3/internal/sequential.hpp"

namespace lptn::td3 {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kObs = 2;

// Everything the training loop needs to know about the data, fixed for the run.
class Environment {
 public:
  Environment(const model::MotorFile& motor, const data::Dataset& dataset, const std::vector<std::size_t>& train,
              const TrainingSettings& settings)
      : model_(motor.model()), dataset_(dataset), train_(train), settings_(settings),
        free_(calibrate::FreeParameters::from_motor(motor)), fixed_(motor.initial_values()) {
    if (free_.size() == 0) throw std::runtime_error("no parameter is marked for calibration in " + motor.path.string());
    const MotorConstants<double>& m = motor.constants;
    const double base_rpm = m.base_speed_rpm();
    obs_scale_ = {base_rpm, m.rated_power_w / (2 * std::numbers::pi * base_rpm / 60.0)};
    for (std::size_t c : train) {
      const data::Cycle& cycle = dataset.cycles[c];
      if (cycle.steps < 2) throw std::runtime_error(cycle.file.string() + ": cycle '" + cycle.name + "' is too short for an episode");
      if (std::abs(cycle.dt_s - settings.agent_sample_time_s) > 1e-9)
        throw std::runtime_error(cycle.file.string() + ": grid step " + std::to_string(cycle.dt_s) +
                                 " s differs from agent_sample_time_s " + std::to_string(settings.agent_sample_time_s));
    }
  }

  std::size_t actions() const { return free_.size(); }
  const calibrate::FreeParameters& free() const { return free_; }
  const Model<double>& model() const { return model_; }
  std::array<double, 2> obs_scale() const { return obs_scale_; }
  std::size_t cycles() const { return train_.size(); }
  const data::Dataset& dataset() const { return dataset_; }
  const std::vector<std::size_t>& train() const { return train_; }
  const data::Cycle& cycle(std::size_t i) const { return dataset_.cycles[train_[i]]; }
  // The unmeasured nodes' start for parameters `p`: the metrics' own fit (estimate_initial_offsets),
  // so that every set is scored on the objective its metrics report, not with offsets that belong
  // to another set.
  model::InitialOffsets<double> offsets_for(std::size_t i, const ParamVector<double>& p) const {
    return model::estimate_initial_offsets(model_, p, cycle(i));
  }

  void observe(const data::Cycle& cycle, std::size_t k, float* obs) const {
    const float torque = cycle.at(data::Channel::torque_nm, k);
    obs[0] = static_cast<float>(cycle.at(data::Channel::speed_rpm, k) / obs_scale_[0]);
    obs[1] = std::isnan(torque) ? 0.0f : static_cast<float>(torque / obs_scale_[1]);
  }

  // Action in [-1, 1]^P onto the full parameter vector.
  ParamVector<double> params_for(const float* action) const {
    ParamVector<double> p = fixed_;
    for (std::size_t j = 0; j < free_.size(); ++j)
      p[free_.index[j]] = from_normalized(static_cast<double>(std::clamp(action[j], -1.0f, 1.0f)), free_.min[j], free_.max[j]);
    return p;
  }

  // Eq. 15 from the step's absolute errors.
  double reward(double stator_abs_k, double rotor_abs_k, bool rotor_measured) const {
    const RewardWeights& w = settings_.reward;
    return -w.w1 / (w.w2 * stator_abs_k + (rotor_measured ? w.w3 : 0.0) * rotor_abs_k + w.w4);
  }

 private:
  Model<double> model_;
  const data::Dataset& dataset_;
  std::vector<std::size_t> train_;
  const TrainingSettings& settings_;
  calibrate::FreeParameters free_;
  ParamVector<double> fixed_;
  std::array<double, 2> obs_scale_{};
};

// Absolute errors of the sensors against the measurement at grid step k (0 where not measured).
struct StepError {
  double stator = 0, rotor = 0;
};
StepError step_error(const Model<double>& model, const double* x, const data::Cycle& cycle, std::size_t k) {
  const float ys = cycle.at(data::Channel::stator_winding_c, k);
  const float yr = cycle.at(data::Channel::rotor_c, k);
  return {std::isnan(ys) ? 0.0 : std::abs(model.stator_sensor(x) - ys), std::isnan(yr) ? 0.0 : std::abs(model.rotor_sensor(x) - yr)};
}

// The run's state between episodes: every formulation's, and the policy's current constant set
// (the warm-up of windows).
struct EpisodeRunState : RunState {
  ParamVector<double> reference{};
};

// What must match for a checkpoint to be continued: the settings and the training data.
nlohmann::json identity(const TrainingSettings& settings, const Environment& env) {
  nlohmann::json cycles = nlohmann::json::array();
  for (std::size_t i = 0; i < env.cycles(); ++i) cycles.push_back({env.cycle(i).name, env.cycle(i).steps});
  nlohmann::json params = nlohmann::json::array();
  for (int i : env.free().index) params.push_back(std::string(param_spec(i).name));
  return {{"settings", to_json(settings)}, {"cycles", cycles}, {"parameters", params}};
}

class Trainer {
 public:
  Trainer(const model::MotorFile& motor, const data::Dataset& dataset, const std::vector<std::size_t>& train,
          const TrainingSettings& settings)
      : settings_(settings), env_(motor, dataset, train, settings),
        agent_(kObs, static_cast<int>(env_.actions()), settings.agent) {
    state_.rng.seed(settings.seed ^ 0x7d3c0ffeeULL);
    set_reference(motor.initial_values());
    uniform_ = std::uniform_real_distribution<float>(-1.0f, 1.0f);
  }

  // The policy's constant set that warms up the per-step episodes' windows, with its offsets per cycle.
  void set_reference(const ParamVector<double>& p) {
    state_.reference = p;
    reference_offsets_.clear();
    for (std::size_t ci = 0; ci < env_.cycles(); ++ci) {
      reference_offsets_.push_back(env_.offsets_for(ci, p));
      state_.simulated_steps += calibrate::evaluation_steps(env_.cycle(ci)) - env_.cycle(ci).steps;  // the offsets' fit
    }
  }

  Agent& agent() { return agent_; }
  const Environment& env() const { return env_; }
  EpisodeRunState& state() { return state_; }

  // Agent steps in an episode on `cycle`: at most max_steps_per_episode, at most the cycle.
  std::size_t episode_length(const data::Cycle& cycle) const {
    return std::min<std::size_t>(static_cast<std::size_t>(settings_.max_steps_per_episode), cycle.steps - 1);
  }

  // One episode: returns its record.
  EpisodeRecord episode() {
    const bool random = state_.done < settings_.random_episodes;
    const std::size_t ci = std::uniform_int_distribution<std::size_t>(0, env_.cycles() - 1)(state_.rng);
    const data::Cycle& cycle = env_.cycle(ci);
    const std::size_t length = episode_length(cycle);
    const std::size_t start = std::uniform_int_distribution<std::size_t>(0, cycle.steps - 1 - length)(state_.rng);
    EpisodeRecord rec;
    rec.episode = state_.done + 1;
    rec.cycle = cycle.name;
    if (settings_.formulation == Formulation::per_step)
      per_step_episode(ci, start, length, random, rec);
    else
      bandit_episode(ci, start, length, random, rec);
    if (!random && settings_.updates_per_episode > 0) state_.updates += agent_.train(settings_.updates_per_episode).updates;
    ++state_.done;
    append_with_average(state_.curve, rec, settings_.averaging_window);
    return state_.curve.back();
  }

  // RMSE over the training cycles (stator and rotor residuals pooled) of a constant set, as the
  // metrics score it: the offsets re-fitted for the set (evaluate_split), on both cores.
  double train_rmse(const ParamVector<double>& p) {
    const calibrate::SplitMetrics m = calibrate::evaluate_split(env_.model(), p, env_.dataset(), env_.train());
    for (std::size_t ci = 0; ci < env_.cycles(); ++ci) state_.simulated_steps += calibrate::evaluation_steps(env_.cycle(ci));
    return model::pool({m.stator, m.rotor}).rmse_k;
  }

  // The deterministic policy's mean reward on the first window of every training cycle.
  double evaluate() {
    double total = 0;
    for (std::size_t ci = 0; ci < env_.cycles(); ++ci) {
      const data::Cycle& cycle = env_.cycle(ci);
      const std::size_t length = episode_length(cycle);
      EpisodeRecord rec;
      if (settings_.formulation == Formulation::per_step) per_step_episode(ci, 0, length, false, rec, false);
      else bandit_episode(ci, 0, length, false, rec, false);
      total += rec.reward;
    }
    return total / static_cast<double>(env_.cycles());
  }

  // The constant set the policy condenses to over the training data's operating points.
  ParamVector<double> condensed() const {
    std::vector<float> obs;
    if (settings_.formulation == Formulation::per_step) {
      for (std::size_t i = 0; i < env_.cycles(); ++i) {
        const data::Cycle& c = env_.cycle(i);
        const auto stride = static_cast<std::size_t>(std::max(1.0, 5.0 / c.dt_s));
        for (std::size_t k = 0; k < c.steps; k += stride) {
          float o[kObs];
          env_.observe(c, k, o);
          obs.insert(obs.end(), o, o + kObs);
        }
      }
    } else {
      for (std::size_t i = 0; i < env_.cycles(); ++i) {
        const data::Cycle& c = env_.cycle(i);
        const auto length = episode_length(c);
        for (std::size_t s = 0; s + length < c.steps; s += length) {
          float o[kObs];
          context(c, 0, s + length, o);
          obs.insert(obs.end(), o, o + kObs);
        }
      }
    }
    const std::size_t n = obs.size() / kObs, p = env_.actions();
    std::vector<float> actions(n * p);
    agent_.act(obs.data(), n, actions.data());
    std::vector<float> mean(p, 0.0f);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < p; ++j) mean[j] += actions[i * p + j] / static_cast<float>(n);
    return env_.params_for(mean.data());
  }

 private:
  // The state at grid step `start`: the model run from the cycle's start with `p`.
  void warm_up(std::size_t ci, std::size_t start, const ParamVector<double>& p, const model::InitialOffsets<double>& offsets,
               double* x) {
    const data::Cycle& cycle = env_.cycle(ci);
    state_.simulated_steps += start;
    model::initial_state_for(env_.model(), cycle, x, offsets);
    for (std::size_t k = 0; k < start; ++k) env_.model().step(x, model::inputs_at(cycle, k), p.data(), cycle.dt_s);
  }

  // Exploration: before learning, uniform random actions (one per hold period); after, Gaussian
  // noise on the policy's action, one draw held for exploration_hold_steps (0: the whole episode).
  void explore(float* a, std::size_t steps, bool random) {
    const std::size_t p = env_.actions();
    const std::size_t hold = settings_.exploration_hold_steps > 0 ? static_cast<std::size_t>(settings_.exploration_hold_steps) : steps;
    const double progress = settings_.max_episodes > 1 ? static_cast<double>(state_.done) / (settings_.max_episodes - 1) : 1.0;
    const double sigma = settings_.exploration_noise + (settings_.exploration_noise_final - settings_.exploration_noise) * progress;
    std::normal_distribution<float> noise(0.0f, static_cast<float>(sigma));
    std::vector<float> draw(p);
    for (std::size_t t = 0; t < steps; ++t) {
      if (t % hold == 0)
        for (std::size_t j = 0; j < p; ++j) draw[j] = random ? uniform_(state_.rng) : noise(state_.rng);
      for (std::size_t j = 0; j < p; ++j) a[t * p + j] = random ? draw[j] : std::clamp(a[t * p + j] + draw[j], -1.0f, 1.0f);
    }
  }

  void per_step_episode(std::size_t ci, std::size_t start, std::size_t length, bool random, EpisodeRecord& rec,
                        bool learn = true) {
    const data::Cycle& cycle = env_.cycle(ci);
    const std::size_t p = env_.actions();
    obs_.resize((length + 1) * kObs);
    for (std::size_t t = 0; t <= length; ++t) env_.observe(cycle, start + t, &obs_[t * kObs]);
    act_.resize(length * p);
    if (!random) agent_.act(obs_.data(), length, act_.data());
    if (learn) explore(act_.data(), length, random);
    double x[kMaxStates];
    warm_up(ci, start, state_.reference, reference_offsets_[ci], x);
    rew_.resize(length);
    state_.simulated_steps += length;
    done_.assign(length, 0);
    done_.back() = 1;
    const bool rotor = cycle.has(data::Channel::rotor_c);
    double reward_sum = 0, error_sum = 0;
    for (std::size_t t = 0; t < length; ++t) {
      const ParamVector<double> params = env_.params_for(&act_[t * p]);
      env_.model().step(x, model::inputs_at(cycle, start + t), params.data(), cycle.dt_s);
      const StepError e = step_error(env_.model(), x, cycle, start + t + 1);
      rew_[t] = static_cast<float>(env_.reward(e.stator, e.rotor, rotor));
      reward_sum += rew_[t];
      error_sum += e.stator + e.rotor;
    }
    if (learn) agent_.remember(obs_.data(), act_.data(), rew_.data(), obs_.data() + kObs, done_.data(), length);
    rec.reward = reward_sum / static_cast<double>(length);
    rec.mean_abs_error_k = error_sum / static_cast<double>(length);
  }

  // The episode's context: its mean normalized speed and torque.
  void context(const data::Cycle& cycle, std::size_t start, std::size_t length, float* ctx) const {
    double sum[kObs] = {0, 0};
    for (std::size_t t = 0; t < length; ++t) {
      float o[kObs];
      env_.observe(cycle, start + t, o);
      sum[0] += o[0];
      sum[1] += o[1];
    }
    ctx[0] = static_cast<float>(sum[0] / static_cast<double>(length));
    ctx[1] = static_cast<float>(sum[1] / static_cast<double>(length));
  }

  void bandit_episode(std::size_t ci, std::size_t start, std::size_t length, bool random, EpisodeRecord& rec,
                      bool learn = true) {
    const data::Cycle& cycle = env_.cycle(ci);
    const std::size_t p = env_.actions();
    float ctx[kObs];
    context(cycle, 0, start + length, ctx);  // of the stretch the reward scores
    std::vector<float> a(p);
    if (!random) agent_.act(ctx, 1, a.data());
    if (learn) explore(a.data(), 1, random);
    const ParamVector<double> params = env_.params_for(a.data());
    // The action holds from the cycle's start, so the whole stretch [0, start + length) is scored:
    // one random window alone varies between windows as much as 1.0x and 1.1x LM differ.
    double x[kMaxStates];
    model::initial_state_for(env_.model(), cycle, x, env_.offsets_for(ci, params));
    state_.simulated_steps += calibrate::evaluation_steps(cycle) - cycle.steps + start + length;
    const bool rotor = cycle.has(data::Channel::rotor_c);
    double stator_sum = 0, rotor_sum = 0;
    for (std::size_t k = 0; k < start + length; ++k) {
      env_.model().step(x, model::inputs_at(cycle, k), params.data(), cycle.dt_s);
      const StepError e = step_error(env_.model(), x, cycle, k + 1);
      stator_sum += e.stator;
      rotor_sum += e.rotor;
    }
    length += start;
    const double n = static_cast<double>(length);
    // The episode's error as the reward: eq. 15's weighted error, -ln(w2 |e_s| + w3 |e_r| + w4)
    // with the errors averaged over the episode. One number per episode makes a bandit; the
    // logarithm keeps the critic's targets on one scale from 300 K off down to the sensors' noise,
    // where 1/(error + w4) would be flat but near the optimum and -error dominated by the worst.
    const RewardWeights& w = settings_.reward;
    const float r = static_cast<float>(-std::log(w.w2 * stator_sum / n + (rotor ? w.w3 : 0.0) * rotor_sum / n + w.w4));
    const std::uint8_t done = 1;
    if (learn) agent_.remember(ctx, a.data(), &r, ctx, &done, 1);
    rec.reward = r;
    rec.mean_abs_error_k = (stator_sum + rotor_sum) / n;
  }

  const TrainingSettings& settings_;
  Environment env_;
  Agent agent_;
  EpisodeRunState state_;
  std::uniform_real_distribution<float> uniform_;
  std::vector<model::InitialOffsets<double>> reference_offsets_;  // of state_.reference, per training cycle
  std::vector<float> obs_, act_, rew_;
  std::vector<std::uint8_t> done_;
};

void save_checkpoint(Trainer& trainer, const std::filesystem::path& dir, const nlohmann::json& id) {
  const EpisodeRunState& s = trainer.state();
  nlohmann::json j = run_state_json(s, "best_episode");
  j["reference"] = std::vector<double>(s.reference.begin(), s.reference.end());
  write_checkpoint(dir, trainer.agent(), s.done, id, std::move(j));
}

void load_checkpoint(Trainer& trainer, const std::filesystem::path& dir, const nlohmann::json& id) {
  const nlohmann::json j = read_checkpoint(dir, id, trainer.agent());
  read_run_state(j, "best_episode", trainer.state());
  ParamVector<double> reference{};
  const auto ref = j.at("reference").get<std::vector<double>>();
  std::copy(ref.begin(), ref.end(), reference.begin());
  trainer.set_reference(reference);
}

}  // namespace

nlohmann::json to_json(const EpisodeRecord& r) {
  return {{"episode", r.episode}, {"cycle", r.cycle}, {"reward", r.reward}, {"average", r.average},
          {"mean_abs_error_k", r.mean_abs_error_k}, {"seconds", r.seconds},
          {"evaluation", std::isnan(r.evaluation) ? nlohmann::json(nullptr) : nlohmann::json(r.evaluation)}};
}

calibrate::SplitMetrics evaluate_scheduled_actor(const Td3Outcome& o, const model::MotorFile& motor, const data::Dataset& dataset,
                                      const std::vector<std::size_t>& cycles) {
  const Model<double> model = motor.model();
  const calibrate::FreeParameters free = calibrate::FreeParameters::from_motor(motor);
  const ActorWeightsPlain& w = o.actor;
  const ActorView actor{w.inputs, w.hidden, w.outputs, w.w1.data(), w.b1.data(), w.w2.data(), w.b2.data(), w.w3.data(), w.b3.data()};
  if (w.inputs != kObs || static_cast<std::size_t>(w.outputs) != free.size())
    throw std::invalid_argument("evaluate_scheduled_actor: the outcome's actor does not map an operating point to these parameters");
  calibrate::SplitMetrics out;
  out.cycles.resize(cycles.size());
  hostio::parallel_for(cycles.size(), hostio::worker_threads(), [&](std::size_t i) {
    const data::Cycle& cycle = dataset.cycles[cycles[i]];
    model::CycleSimulation sim;
    sim.stator_sensor.reserve(cycle.steps);
    sim.rotor_sensor.reserve(cycle.steps);
    double x[kMaxStates];
    model::initial_state_for(model, cycle, x, model::estimate_initial_offsets(model, o.values, cycle));
    auto record = [&] {
      sim.stator_sensor.push_back(static_cast<float>(model.stator_sensor(x)));
      sim.rotor_sensor.push_back(static_cast<float>(model.rotor_sensor(x)));
    };
    record();
    for (std::size_t k = 0; k + 1 < cycle.steps; ++k) {
      ParamVector<double> p = o.values;
      const float torque = cycle.at(data::Channel::torque_nm, k);
      if (!std::isnan(torque)) {
        const float obs[kObs] = {static_cast<float>(cycle.at(data::Channel::speed_rpm, k) / o.obs_scale[0]),
                                 static_cast<float>(torque / o.obs_scale[1])};
        float u[32];
        if (actor_forward<256, 32>(actor, obs, u))
          for (std::size_t j = 0; j < free.size(); ++j)
            p[free.index[j]] = from_normalized(static_cast<double>(u[j]), free.min[j], free.max[j]);
      }
      model.step(x, model::inputs_at(cycle, k), p.data(), cycle.dt_s);
      record();
    }
    out.cycles[i].name = cycle.name;
    out.cycles[i].stator = model::compare(sim.stator_sensor, cycle, data::Channel::stator_winding_c);
    out.cycles[i].rotor = model::compare(sim.rotor_sensor, cycle, data::Channel::rotor_c);
  });
  calibrate::pool_cycles(out);
  return out;
}

EpisodeRecord record_from_json(const nlohmann::json& r) {
  return {r.at("episode").get<int>(), r.at("cycle").get<std::string>(), r.at("reward").get<double>(),
          r.at("average").get<double>(), r.at("mean_abs_error_k").get<double>(), r.at("seconds").get<double>(),
          r.at("evaluation").is_null() ? std::nan("") : r.at("evaluation").get<double>()};
}

Td3Outcome train_td3(const model::MotorFile& motor, const data::Dataset& dataset, const std::vector<std::size_t>& train,
                     const TrainingSettings& settings, const std::filesystem::path& checkpoint_dir, bool resume,
                     const Td3Progress& progress, const WarmStart& warm) {
  if (train.empty()) throw std::runtime_error("no training cycle");
  if (settings.formulation == Formulation::sequential)
    return train_sequential(motor, dataset, train, settings, checkpoint_dir, resume, progress, warm);
  if (!warm.agent_file.empty()) throw std::runtime_error("a warm start is for the sequential formulation (--method td3) only");
  Trainer trainer(motor, dataset, train, settings);
  const nlohmann::json id = identity(settings, trainer.env());
  Td3Outcome out;
  EpisodeRunState& s = trainer.state();
  if (resume) {
    load_checkpoint(trainer, checkpoint_dir, id);
    out.resumed_from = s.done;
  }
  if (!resume) {
    s.initial_evaluation = trainer.evaluate();
    s.best = motor.initial_values();
    s.best_train_rmse_k = trainer.train_rmse(s.best);
  }
  const auto t0 = Clock::now();
  const double seconds_before = s.seconds;
  const int first = s.done;
  out.completed = true;
  while (s.done < settings.max_episodes) {
    const EpisodeRecord rec = trainer.episode();
    s.seconds = seconds_before + std::chrono::duration<double>(Clock::now() - t0).count();
    s.curve.back().seconds = s.seconds;
    const bool reached = s.done >= settings.averaging_window && rec.average >= settings.stop_average_reward;
    if (s.done % settings.checkpoint_every == 0 || reached || s.done == settings.max_episodes) {
      trainer.set_reference(trainer.condensed());
      s.curve.back().evaluation = trainer.evaluate();
      const double rmse = trainer.train_rmse(s.reference);
      if (rmse < s.best_train_rmse_k) {
        s.best = s.reference;
        s.best_train_rmse_k = rmse;
        s.best_at = s.done;
      }
      save_checkpoint(trainer, checkpoint_dir, id);
    }
    if (progress) {
      const EpisodeReport r = progress_report(rec, s.done, settings.max_episodes, first, s.seconds, seconds_before,
                                              s.done <= settings.random_episodes);
      if (!progress(r)) {
        out.completed = false;
        break;
      }
    }
    if (reached) {
      out.reached_target = true;
      break;
    }
  }
  take_run_state(s, out);
  out.actor = trainer.agent().actor_weights();
  out.param_indices = trainer.env().free().index;
  out.obs_scale = trainer.env().obs_scale();
  // A spread of operating points for exported forward passes to prove themselves against.
  out.check_obs = {0.0f, 0.0f, 0.25f, 0.5f, 0.5f, 1.0f, 1.0f, 1.0f, 1.5f, -0.5f, 0.1f, -1.0f, 2.0f, 2.0f, 0.75f, 0.1f};
  const std::size_t checks = out.check_obs.size() / kObs;
  out.check_actions.resize(checks * trainer.env().actions());
  trainer.agent().act(out.check_obs.data(), checks, out.check_actions.data());
  return out;
}

}  // namespace lptn::td3
