// Calibration as a sequential decision problem, for TD3 proper: the agent walks the parameter
// space in a few shrinking steps, seeing where it stands (the normalized set) and what the data
// say about it (features of the residuals, set_scorer.hpp), rewarded with the fall in the log of
// the pooled training RMSE. Rewards telescope: an episode's return is how far the error fell from
// its random start. Several episodes run side by side so that each step's sets are simulated
// together on every core. The result is the actor's: the best set its deterministic rollouts
// visit, re-scored on the data's own grid as the metrics score it.
#include "trainer/td3/internal/sequential.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <stdexcept>

#include "hostio/worker_threads.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/calibrate/set_scorer.hpp"
#include "trainer/data/coarse_grid.hpp"
#include "trainer/td3/internal/checkpoint.hpp"
#include "trainer/td3/internal/run_record.hpp"

namespace lptn::td3 {
namespace {

using Clock = std::chrono::steady_clock;

std::vector<data::Cycle> coarse_cycles(const data::Dataset& dataset, const std::vector<std::size_t>& train, int factor) {
  std::vector<data::Cycle> out;
  for (std::size_t c : train) out.push_back(data::coarse_grid(dataset.cycles[c], factor));
  return out;
}

class SequentialTrainer {
 public:
  SequentialTrainer(const model::MotorFile& motor, const data::Dataset& dataset, const std::vector<std::size_t>& train,
                    const TrainingSettings& settings, const WarmStart& warm)
      : settings_(settings), warm_(!warm.agent_file.empty()), q_(settings.sequential), dataset_(dataset), train_(train), model_(motor.model()),
        free_(calibrate::FreeParameters::from_motor(motor)),
        scorer_(model_, free_, motor.initial_values(), coarse_cycles(dataset, train, q_.coarse_factor)),
        p_(free_.size()), obs_dim_(p_ + calibrate::SetScorer::features() + 1),
        agent_(static_cast<int>(obs_dim_), static_cast<int>(p_), settings.agent) {
    if (p_ == 0) throw std::runtime_error("no parameter is marked for calibration in " + motor.path.string());
    if (warm_) agent_.load_networks(warm.agent_file);
    const ParamVector<double> guess = motor.initial_values();
    for (std::size_t j = 0; j < p_; ++j) guess_.push_back(to_normalized(guess[free_.index[j]], free_.min[j], free_.max[j]));
    state_.rng.seed(settings.seed ^ 0x5e9c0ffeeULL);
    // The rollouts that make the result start from the guess and from fixed draws around it.
    std::mt19937_64 fixed(settings.seed ^ 0x0123abcdULL);
    rollout_starts_ = guess_;
    for (int k = 1; k < q_.rollout_starts; ++k) {
      const std::vector<double> u = start(fixed);
      rollout_starts_.insert(rollout_starts_.end(), u.begin(), u.end());
    }
  }

  Agent& agent() { return agent_; }
  RunState& state() { return state_; }
  const calibrate::FreeParameters& free() const { return free_; }
  std::size_t obs_dim() const { return obs_dim_; }

  // One round: `environments` episodes side by side. Returns its record.
  EpisodeRecord round() {
    const std::size_t n = static_cast<std::size_t>(q_.environments);
    // A warm start knows where to go: no random rounds, and exploration from twice its floor.
    const bool random = !warm_ && state_.done < settings_.random_episodes;
    const double progress = settings_.max_episodes > 1 ? static_cast<double>(state_.done) / (settings_.max_episodes - 1) : 1.0;
    const double first = warm_ ? std::min(settings_.exploration_noise, 2 * settings_.exploration_noise_final) : settings_.exploration_noise;
    const double last = settings_.exploration_noise_final;
    const double sigma = last > 0 && first > 0 ? first * std::pow(last / first, progress) : first + (last - first) * progress;
    std::vector<double> u;
    for (std::size_t e = 0; e < n; ++e) {
      const std::vector<double> s = start(state_.rng);
      u.insert(u.end(), s.begin(), s.end());
    }
    std::vector<calibrate::SetScore> now = score(u, n);
    const std::vector<double> first_rmse = rmse_of(now);
    std::vector<float> obs(n * obs_dim_), next_obs(n * obs_dim_), a(n * p_), r(n);
    std::vector<std::uint8_t> done(n);
    std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
    std::normal_distribution<float> noise(0.0f, static_cast<float>(sigma));
    for (int t = 0; t < q_.steps_per_episode; ++t) {
      for (std::size_t e = 0; e < n; ++e) observe(&u[e * p_], now[e], t, &obs[e * obs_dim_]);
      if (random) {
        for (float& x : a) x = uniform(state_.rng);
      } else {
        agent_.act(obs.data(), n, a.data());
        for (float& x : a) x = std::clamp(x + noise(state_.rng), -1.0f, 1.0f);
      }
      const std::vector<double> next = stepped(u, a, t, n);
      const std::vector<calibrate::SetScore> after = score(next, n);
      for (std::size_t e = 0; e < n; ++e) {
        r[e] = static_cast<float>(std::log(now[e].rmse_k) - std::log(after[e].rmse_k));
        observe(&next[e * p_], after[e], t + 1, &next_obs[e * obs_dim_]);
        done[e] = t + 1 == q_.steps_per_episode;
      }
      agent_.remember(obs.data(), a.data(), r.data(), next_obs.data(), done.data(), n);
      if (!random && q_.updates_per_step > 0) state_.updates += agent_.train(q_.updates_per_step).updates;
      u = next;
      now = after;
    }
    EpisodeRecord rec;
    rec.episode = state_.done + 1;
    rec.cycle = "all";
    for (std::size_t e = 0; e < n; ++e) {
      rec.reward += (std::log(first_rmse[e]) - std::log(now[e].rmse_k)) / static_cast<double>(n);
      rec.mean_abs_error_k += now[e].rmse_k / static_cast<double>(n);
    }
    ++state_.done;
    append_with_average(state_.curve, rec, settings_.averaging_window);
    return state_.curve.back();
  }

  // The deterministic actor's rollouts from the fixed starts: their mean fall in ln RMSE, and the
  // best set they visit (on the training grid) is offered as the result after a re-score on the
  // data's own grid with the metrics' offsets.
  double evaluate_and_offer() {
    const std::size_t n = rollout_starts_.size() / p_;
    std::vector<double> u = rollout_starts_;
    std::vector<calibrate::SetScore> now = score(u, n);
    const std::vector<double> first = rmse_of(now);
    std::vector<std::pair<double, std::vector<double>>> visited;
    auto visit = [&] {
      for (std::size_t e = 0; e < n; ++e)
        visited.emplace_back(now[e].rmse_k, std::vector<double>(u.begin() + e * p_, u.begin() + (e + 1) * p_));
    };
    visit();
    std::vector<float> obs(n * obs_dim_), a(n * p_);
    for (int t = 0; t < q_.steps_per_episode; ++t) {
      for (std::size_t e = 0; e < n; ++e) observe(&u[e * p_], now[e], t, &obs[e * obs_dim_]);
      agent_.act(obs.data(), n, a.data());
      u = stepped(u, a, t, n);
      now = score(u, n);
      visit();
    }
    double fall = 0;
    for (std::size_t e = 0; e < n; ++e) fall += (std::log(first[e]) - std::log(now[e].rmse_k)) / static_cast<double>(n);
    std::stable_sort(visited.begin(), visited.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    constexpr std::size_t kRescored = 3;
    for (std::size_t i = 0; i < std::min(kRescored, visited.size()); ++i) {
      const ParamVector<double> p = scorer_.params_for(visited[i].second.data());
      const double rmse = train_rmse(p);
      if (rmse < state_.best_train_rmse_k) {
        state_.best = p;
        state_.best_train_rmse_k = rmse;
        state_.best_at = state_.done;
      }
    }
    return fall;
  }

  // On the data's own grid with the offsets re-fitted, stator and rotor pooled: the metrics' figure.
  double train_rmse(const ParamVector<double>& p) {
    const calibrate::SplitMetrics m = calibrate::evaluate_split(model_, p, dataset_, train_);
    for (std::size_t c : train_) state_.simulated_steps += calibrate::evaluation_steps(dataset_.cycles[c]);
    return model::pool({m.stator, m.rotor}).rmse_k;
  }

 private:
  template <class Rng>
  std::vector<double> start(Rng& rng) const {
    std::uniform_real_distribution<double> d(-q_.start_spread, q_.start_spread);
    std::vector<double> u(p_);
    for (std::size_t j = 0; j < p_; ++j) u[j] = std::clamp(guess_[j] + d(rng), -1.0, 1.0);
    return u;
  }

  std::vector<double> stepped(const std::vector<double>& u, const std::vector<float>& a, int t, std::size_t n) const {
    const double size = q_.step_scale * std::pow(q_.step_decay, t);
    std::vector<double> next(n * p_);
    for (std::size_t i = 0; i < n * p_; ++i) next[i] = std::clamp(u[i] + size * static_cast<double>(a[i]), -1.0, 1.0);
    return next;
  }

  std::vector<calibrate::SetScore> score(const std::vector<double>& u, std::size_t n) {
    std::vector<calibrate::SetScore> out(n);
    scorer_.score(u.data(), n, out.data(), hostio::worker_threads());
    for (const calibrate::SetScore& s : out) state_.simulated_steps += s.simulated_steps;
    return out;
  }

  static std::vector<double> rmse_of(const std::vector<calibrate::SetScore>& s) {
    std::vector<double> out;
    for (const calibrate::SetScore& x : s) out.push_back(x.rmse_k);
    return out;
  }

  void observe(const double* u, const calibrate::SetScore& s, int t, float* obs) const {
    for (std::size_t j = 0; j < p_; ++j) obs[j] = static_cast<float>(u[j]);
    std::copy(s.features.begin(), s.features.end(), obs + p_);
    obs[obs_dim_ - 1] = static_cast<float>(t) / static_cast<float>(q_.steps_per_episode);
  }

  const TrainingSettings& settings_;
  bool warm_;
  const SequentialSettings& q_;
  const data::Dataset& dataset_;
  std::vector<std::size_t> train_;
  Model<double> model_;
  calibrate::FreeParameters free_;
  calibrate::SetScorer scorer_;
  std::size_t p_, obs_dim_;
  Agent agent_;
  RunState state_;
  std::vector<double> guess_, rollout_starts_;
};

nlohmann::json identity(const TrainingSettings& settings, const data::Dataset& dataset, const std::vector<std::size_t>& train,
                        const calibrate::FreeParameters& free, const WarmStart& warm) {
  nlohmann::json cycles = nlohmann::json::array();
  for (std::size_t c : train) cycles.push_back({dataset.cycles[c].name, dataset.cycles[c].steps});
  nlohmann::json params = nlohmann::json::array();
  for (std::size_t j = 0; j < free.size(); ++j)
    params.push_back({std::string(param_spec(free.index[j]).name), free.min[j], free.max[j]});
  return {{"settings", to_json(settings)}, {"cycles", cycles}, {"parameters", params}, {"warm_start", warm.sha256}};
}

// Returns the agent file it wrote.
std::filesystem::path save_checkpoint(SequentialTrainer& trainer, const std::filesystem::path& dir, const nlohmann::json& id) {
  const RunState& s = trainer.state();
  // Rounds, under the key every formulation's checkpoint uses.
  return write_checkpoint(dir, trainer.agent(), s.done, id, run_state_json(s, "best_round"));
}

void load_checkpoint(SequentialTrainer& trainer, const std::filesystem::path& dir, const nlohmann::json& id) {
  read_run_state(read_checkpoint(dir, id, trainer.agent()), "best_round", trainer.state());
}

}  // namespace

Td3Outcome train_sequential(const model::MotorFile& motor, const data::Dataset& dataset, const std::vector<std::size_t>& train,
                            const TrainingSettings& settings, const std::filesystem::path& checkpoint_dir, bool resume,
                            const Td3Progress& progress, const WarmStart& warm) {
  SequentialTrainer trainer(motor, dataset, train, settings, warm);
  const nlohmann::json id = identity(settings, dataset, train, trainer.free(), warm);
  Td3Outcome out;
  RunState& s = trainer.state();
  const auto t0 = Clock::now();
  if (resume) {
    load_checkpoint(trainer, checkpoint_dir, id);
    out.resumed_from = s.done;
  } else {
    s.best = motor.initial_values();
    s.best_train_rmse_k = trainer.train_rmse(s.best);
    s.initial_evaluation = trainer.evaluate_and_offer();
  }
  const double seconds_before = s.seconds;
  const int first = s.done;
  out.completed = true;
  while (s.done < settings.max_episodes) {
    const EpisodeRecord rec = trainer.round();
    s.seconds = seconds_before + std::chrono::duration<double>(Clock::now() - t0).count();
    if (s.done % settings.checkpoint_every == 0 || s.done == settings.max_episodes) {
      s.curve.back().evaluation = trainer.evaluate_and_offer();
      s.seconds = seconds_before + std::chrono::duration<double>(Clock::now() - t0).count();
      s.curve.back().seconds = s.seconds;
      out.agent_file = save_checkpoint(trainer, checkpoint_dir, id);
      out.best_at_checkpoints.emplace_back(s.done, s.best);
      out.checkpoint_seconds.push_back(s.seconds);
    }
    s.curve.back().seconds = s.seconds;
    if (progress) {
      const EpisodeReport r = progress_report(rec, s.done, settings.max_episodes, first, s.seconds, seconds_before,
                                              warm.agent_file.empty() && s.done <= settings.random_episodes);
      if (!progress(r)) {
        out.completed = false;
        break;
      }
    }
  }
  take_run_state(s, out);
  out.actor = trainer.agent().actor_weights();
  out.param_indices = trainer.free().index;
  return out;
}

}  // namespace lptn::td3
