#include "trainer/td3/td3_settings.hpp"

#include <cmath>
#include <set>
#include <sstream>
#include <toml++/toml.h>

namespace lptn::td3 {
namespace {

// Reads one table's keys over existing values; anything unknown or out of range is an error
// naming the file, the line and the key.
class Reader {
 public:
  Reader(const toml::table& table, std::string prefix, const std::filesystem::path& file)
      : table_(table), prefix_(std::move(prefix)), file_(file) {}

  [[noreturn]] void fail(const toml::source_region& where, std::string_view key, std::string_view reason) const {
    std::ostringstream s;
    s << file_.string() << ':' << where.begin.line << ": key '" << prefix_ << key << "': " << reason;
    throw SettingsError(s.str());
  }

  void number(std::string_view key, double& out, double min, double max) {
    known_.insert(std::string(key));
    const toml::node* node = table_.get(key);
    if (!node) return;
    const auto v = node->value<double>();
    if (!v || !std::isfinite(*v)) fail(node->source(), key, "must be a finite number");
    if (*v < min || *v > max) {
      std::ostringstream s;
      s << "must lie between " << min << " and " << max;
      fail(node->source(), key, s.str());
    }
    out = *v;
  }

  template <class Int>
  void integer(std::string_view key, Int& out, long long min, long long max) {
    known_.insert(std::string(key));
    const toml::node* node = table_.get(key);
    if (!node) return;
    const auto v = node->value<long long>();
    if (!v || !node->is_integer()) fail(node->source(), key, "must be an integer");
    if (*v < min || *v > max) fail(node->source(), key, "must lie between " + std::to_string(min) + " and " + std::to_string(max));
    out = static_cast<Int>(*v);
  }

  const toml::table* table(std::string_view key) {
    known_.insert(std::string(key));
    const toml::node* node = table_.get(key);
    if (!node) return nullptr;
    if (!node->as_table()) fail(node->source(), key, "must be a table");
    return node->as_table();
  }

  void refuse_unknown() const {
    for (const auto& [key, node] : table_)
      if (!known_.count(std::string(key.str()))) fail(node.source(), key.str(), "unknown key");
  }

 private:
  const toml::table& table_;
  std::string prefix_;
  const std::filesystem::path& file_;
  std::set<std::string> known_;
};

}  // namespace

const char* to_string(Formulation f) {
  switch (f) {
    case Formulation::sequential: return "td3";
    case Formulation::per_step: return "td3-paper";
    default: return "td3-episode";
  }
}

Formulation formulation_from_method(const std::string& method) {
  for (Formulation f : {Formulation::sequential, Formulation::per_step, Formulation::episode})
    if (method == to_string(f)) return f;
  throw std::invalid_argument("no TD3 formulation is called '" + method + "'");
}

TrainingSettings default_settings(Formulation formulation) {
  TrainingSettings s;
  s.formulation = formulation;
  s.agent.actor_lr = 1e-4;  // see TrainingSettings::updates_per_episode
  if (formulation == Formulation::episode) {
    // One transition per episode: the buffer holds every episode, updates are cheap per episode.
    s.updates_per_episode = 50;
    s.random_episodes = 25;
    s.exploration_noise = 0.2;
    s.agent.batch_size = 64;
    s.agent.gamma = 0.0;  // a bandit: nothing follows the action
    s.agent.actor_lr = 1e-3;
    s.exploration_noise_final = 0.01;
    s.stop_average_reward = 0.1;  // reward = -ln(mean |error| in K + 0.1): the sensors' noise floor is about 0.8 K
  }
  if (formulation == Formulation::sequential) {
    // Episodes are counted in rounds of SequentialSettings::environments; the reward (the fall
    // in ln RMSE over an episode) depends on where it started, so no average of it ends a run.
    s.max_episodes = 1200;
    s.averaging_window = 20;
    s.stop_average_reward = 1e30;
    s.random_episodes = 10;
    s.exploration_noise = 0.3;
    s.exploration_noise_final = 0.05;
    s.checkpoint_every = 20;
    s.updates_per_episode = 0;  // updates_per_step instead
    s.agent.hidden = 128;
    s.agent.actor_lr = 1e-3;
    s.agent.gamma = 0.95;
    s.agent.buffer_capacity = 50'000;  // recent transitions: the critic learns the landscape the actor now visits
  }
  return s;
}

TrainingSettings load_settings(const std::filesystem::path& file, Formulation formulation) {
  TrainingSettings s = default_settings(formulation);
  toml::table root;
  try {
    root = toml::parse_file(file.string());
  } catch (const toml::parse_error& e) {
    std::ostringstream m;
    m << file.string() << ':' << e.source().begin.line << ": " << e.description();
    throw SettingsError(m.str());
  }
  Reader top(root, "", file);
  top.integer("max_episodes", s.max_episodes, 1, 10'000'000);
  top.integer("averaging_window", s.averaging_window, 1, 100'000);
  top.number("stop_average_reward", s.stop_average_reward, -1e30, 1e30);
  top.integer("max_steps_per_episode", s.max_steps_per_episode, 1, 100'000'000);
  top.number("agent_sample_time_s", s.agent_sample_time_s, 1e-6, 1e6);
  top.number("exploration_noise", s.exploration_noise, 0.0, 10.0);
  top.number("exploration_noise_final", s.exploration_noise_final, 0.0, 10.0);
  top.integer("exploration_hold_steps", s.exploration_hold_steps, 0, 100'000'000);
  top.integer("random_episodes", s.random_episodes, 0, 10'000'000);
  top.integer("updates_per_episode", s.updates_per_episode, 0, 100'000'000);
  top.integer("checkpoint_every", s.checkpoint_every, 1, 10'000'000);
  top.integer("seed", s.seed, 0, std::numeric_limits<long long>::max());
  if (const toml::table* t = top.table("agent")) {
    Reader r(*t, "agent.", file);
    r.integer("hidden", s.agent.hidden, 1, 4096);
    r.number("actor_lr", s.agent.actor_lr, 0.0, 1.0);
    r.number("critic_lr", s.agent.critic_lr, 0.0, 1.0);
    r.number("gamma", s.agent.gamma, 0.0, 1.0);
    r.number("tau", s.agent.tau, 0.0, 1.0);
    r.number("policy_noise", s.agent.policy_noise, 0.0, 10.0);
    r.number("noise_clip", s.agent.noise_clip, 0.0, 10.0);
    r.integer("policy_delay", s.agent.policy_delay, 1, 1000);
    r.integer("batch_size", s.agent.batch_size, 1, 1'000'000);
    r.integer("buffer_capacity", s.agent.buffer_capacity, 1, 100'000'000);
    r.refuse_unknown();
  }
  if (const toml::table* t = top.table("reward")) {
    Reader r(*t, "reward.", file);
    r.number("w1", s.reward.w1, -1e9, 1e9);
    r.number("w2", s.reward.w2, 0.0, 1e9);
    r.number("w3", s.reward.w3, 0.0, 1e9);
    r.number("w4", s.reward.w4, 1e-9, 1e9);
    r.refuse_unknown();
  }
  if (const toml::table* t = top.table("sequential")) {
    if (formulation != Formulation::sequential) Reader(*t, "", file).fail(t->source(), "sequential", "only for --method td3");
    Reader r(*t, "sequential.", file);
    SequentialSettings& q = s.sequential;
    r.integer("steps_per_episode", q.steps_per_episode, 1, 1000);
    r.integer("environments", q.environments, 1, 1024);
    r.number("step_scale", q.step_scale, 1e-6, 2.0);
    r.number("step_decay", q.step_decay, 1e-3, 1.0);
    r.number("start_spread", q.start_spread, 0.0, 2.0);
    r.integer("coarse_factor", q.coarse_factor, 1, 1000);
    r.integer("updates_per_step", q.updates_per_step, 0, 100'000);
    r.integer("rollout_starts", q.rollout_starts, 1, 1000);
    r.refuse_unknown();
  }
  top.refuse_unknown();
  s.agent.seed = s.seed;
  return s;
}

nlohmann::json to_json(const TrainingSettings& s) {
  nlohmann::json j = {{"formulation", to_string(s.formulation)},
          {"max_episodes", s.max_episodes},
          {"averaging_window", s.averaging_window},
          {"stop_average_reward", s.stop_average_reward},
          {"max_steps_per_episode", s.max_steps_per_episode},
          {"agent_sample_time_s", s.agent_sample_time_s},
          {"exploration_noise", s.exploration_noise},
          {"exploration_noise_final", s.exploration_noise_final},
          {"exploration_hold_steps", s.exploration_hold_steps},
          {"random_episodes", s.random_episodes},
          {"updates_per_episode", s.updates_per_episode},
          {"checkpoint_every", s.checkpoint_every},
          {"seed", s.seed},
          {"agent",
           {{"hidden", s.agent.hidden},
            {"actor_lr", s.agent.actor_lr},
            {"critic_lr", s.agent.critic_lr},
            {"gamma", s.agent.gamma},
            {"tau", s.agent.tau},
            {"policy_noise", s.agent.policy_noise},
            {"noise_clip", s.agent.noise_clip},
            {"policy_delay", s.agent.policy_delay},
            {"batch_size", s.agent.batch_size},
            {"buffer_capacity", s.agent.buffer_capacity}}},
          {"reward", {{"w1", s.reward.w1}, {"w2", s.reward.w2}, {"w3", s.reward.w3}, {"w4", s.reward.w4}}}};
  if (s.formulation == Formulation::sequential) {
    const SequentialSettings& q = s.sequential;
    j["sequential"] = {{"steps_per_episode", q.steps_per_episode}, {"environments", q.environments},
                       {"step_scale", q.step_scale}, {"step_decay", q.step_decay}, {"start_spread", q.start_spread},
                       {"coarse_factor", q.coarse_factor}, {"updates_per_step", q.updates_per_step},
                       {"rollout_starts", q.rollout_starts}};
  }
  return j;
}

}  // namespace lptn::td3
