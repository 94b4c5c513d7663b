// Crash-safe training, as a user meets it: `lptn calibrate --method td3` killed with SIGKILL at
// random moments (during start-up, an episode, an update or a checkpoint's write), then run again
// with --resume, until it finishes. Every kill must leave the last checkpoint readable and an
// earlier result file untouched; the run must end with exactly the result of an uninterrupted run.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "lptn_testing/temp_dir.hpp"

extern char** environ;

namespace lptn::td3 {
namespace {

namespace fs = std::filesystem;

using testing::slurp;

// The lptn binary itself as a child (not through a shell, so that SIGKILL reaches it), its
// output into `log`.
pid_t spawn_lptn(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<std::string> all{LPTN_BINARY};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, LPTN_BINARY, &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return rc == 0 ? pid : -1;
}

// The last checkpoint, where there is one, must be whole: state.json parses and the agent file
// it names exists. Returns its episode (0: none yet).
int checkpoint_episode(const fs::path& dir) {
  const fs::path state = dir / "state.json";
  if (!fs::exists(state)) return 0;
  nlohmann::json j;
  EXPECT_NO_THROW(j = nlohmann::json::parse(slurp(state))) << state;
  if (!j.is_object()) return -1;
  EXPECT_TRUE(fs::exists(dir / j.at("agent_file").get<std::string>())) << j.at("agent_file");
  return j.at("episode").get<int>();
}

// The episode of the newest checkpoint as a watcher sees it while the run goes on (0: none yet,
// or none readable at this instant). The whole-checkpoint checks run only after a kill.
int checkpoint_progress(const fs::path& dir) {
  try {
    const nlohmann::json j = nlohmann::json::parse(slurp(dir / "state.json"));
    return j.at("episode").get<int>();
  } catch (const std::exception&) {
    return 0;
  }
}
// Exit code of a finished child, or -SIGKILL once killed.
int code_of(int status) { return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status); }

using Ms = std::chrono::milliseconds;
Ms since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration_cast<Ms>(std::chrono::steady_clock::now() - t0);
}

// Watches a child: kills it (SIGKILL) once `kill_at(progress)` says so, where `progress` holds the
// times from its start at which each new checkpoint appeared. Returns the exit code (-SIGKILL if
// killed) and those times. A child left alone gets ten minutes.
struct Watched {
  int code = -1;
  std::vector<Ms> checkpoints;  // time from the start to each new checkpoint seen
};
template <class KillAt>
Watched watch(pid_t pid, const fs::path& checkpoint_dir, KillAt&& kill_at) {
  const auto t0 = std::chrono::steady_clock::now();
  Watched w;
  int seen = checkpoint_progress(checkpoint_dir), status = 0;
  while (since(t0) < std::chrono::minutes(10)) {
    if (waitpid(pid, &status, WNOHANG) == pid) {
      w.code = code_of(status);
      return w;
    }
    const int now = checkpoint_progress(checkpoint_dir);
    if (now > seen) {
      seen = now;
      w.checkpoints.push_back(since(t0));
    }
    if (since(t0) >= kill_at(w.checkpoints)) break;
    std::this_thread::sleep_for(Ms(2));
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  w.code = code_of(status);
  return w;
}

// What an interrupted run must reproduce: the parameters and the training curve's rewards (wall
// times differ, as do the file's creation time and the resume record).
nlohmann::json result_of(const fs::path& file) {
  const nlohmann::json j = nlohmann::json::parse(slurp(file));
  nlohmann::json out;
  out["parameters"] = j.at("parameters");
  out["metrics"] = j.at("metrics");
  for (const auto& r : j.at("method").at("details").at("training_curve"))
    out["curve"].push_back({r.at("episode"), r.at("cycle"), r.at("reward"), r.at("evaluation")});
  return out;
}

// A formulation and a budget that runs in seconds, with a checkpoint after every episode (round).
struct Formulation {
  const char* method;
  const char* config;
};
std::ostream& operator<<(std::ostream& o, const Formulation& f) { return o << f.method; }

class Td3CrashSafety : public ::testing::TestWithParam<Formulation> {};

INSTANTIATE_TEST_SUITE_P(
    Formulations, Td3CrashSafety,
    ::testing::Values(Formulation{"td3",
                                "random_episodes = 2\ncheckpoint_every = 1\n[sequential]\nenvironments = 2\nsteps_per_episode = 4\n"
                                "rollout_starts = 2\nupdates_per_step = 40\n[agent]\nhidden = 64\nbatch_size = 64\n"},
                    Formulation{"td3-paper",
                                "max_steps_per_episode = 3000\nrandom_episodes = 2\nupdates_per_episode = 400\n"
                                "checkpoint_every = 1\n[agent]\nhidden = 64\nbatch_size = 64\n"}),
    [](const ::testing::TestParamInfo<Formulation>& i) { return i.param.method == std::string("td3") ? std::string("sequential") : std::string("paper"); });

TEST_P(Td3CrashSafety, KilledAtRandomMomentsAndResumedItEndsWhereAnUninterruptedRunEnds) {
  testing::TempDir dir;
  const fs::path data = dir.path() / "fleet", config = dir.path() / "small.toml";
  const fs::path log = dir.path() / "log.txt";
  ASSERT_EQ(std::system((std::string(LPTN_BINARY) + " generate --out " + data.string() +
                         " --cycles 3 --seed 4 --minutes-min 6 --minutes-max 8 > /dev/null 2>&1").c_str()), 0);
  std::ofstream(config) << GetParam().config;
  const auto args = [&](const std::string& out, const std::string& checkpoints) {
    return std::vector<std::string>{"calibrate", "--data", data.string(), "--motor", (data / "motor.toml").string(),
                                    "--method", GetParam().method, "--config", config.string(), "--episodes", "14", "--seed", "3",
                                    "--out", out, "--checkpoint-dir", checkpoints, "--force", "--quiet"};
  };

  // The uninterrupted run, watched for how long its start-up and its episodes take here, now.
  const fs::path straight = dir.path() / "straight.json";
  const Watched first = watch(spawn_lptn(args(straight.string(), (dir.path() / "straight.ckpt").string()), log),
                              dir.path() / "straight.ckpt", [](const std::vector<Ms>&) { return Ms::max(); });
  // 14 short episodes leave the model short of its sensors' noise: written with warnings (exit 3).
  ASSERT_TRUE(first.code == 0 || first.code == 3) << slurp(log);
  ASSERT_GE(first.checkpoints.size(), 3u) << "a checkpoint after every episode";
  const Ms start_up = first.checkpoints.front();  // start-up and the first episode
  const Ms episode((first.checkpoints.back() - first.checkpoints.front()).count() /
                   static_cast<long long>(first.checkpoints.size() - 1));
  std::printf("uninterrupted run: first checkpoint after %lld ms, then an episode every %lld ms\n",
              static_cast<long long>(start_up.count()), static_cast<long long>(episode.count()));

  // An earlier result in the output's place: no kill may touch it, only the finished run replace it.
  const fs::path out = dir.path() / "killed.json", checkpoints = dir.path() / "killed.ckpt";
  fs::copy_file(straight, out);
  std::ofstream(out, std::ios::app) << "\n";  // told apart from the final result
  const std::string earlier = slurp(out);

  // Random moments, the same ones on every run of the test, set by each attempt's own progress
  // rather than by a wall time measured once, so that the schedule holds on any machine and under
  // any load: attempts in turn are killed during start-up (at a random share of the time the last
  // attempt took to its first new checkpoint) and within the episode after their first new
  // checkpoint (at a random share of an episode's time). Each attempt so gets at most a couple of
  // episodes further, and eight kills leave the 14-episode run well short of its end.
  std::mt19937 rng(20261123);
  std::uniform_real_distribution<double> share(0.05, 0.95);
  int kills = 0, code = -1, last_episode = 0;
  Ms to_first_checkpoint = start_up;
  std::vector<int> episodes;
  for (int attempt = 0; attempt < 40 && code != 0; ++attempt) {
    std::vector<std::string> a = args(out.string(), checkpoints.string());
    if (fs::exists(checkpoints / "state.json")) a.push_back("--resume");
    const bool kill_this_one = kills < 8;
    const bool in_start_up = kills % 2 == 0;
    const double s = share(rng);
    const Watched w = watch(spawn_lptn(a, log), checkpoints, [&](const std::vector<Ms>& seen) {
      if (!kill_this_one) return Ms::max();
      if (in_start_up) return Ms(static_cast<long long>(s * static_cast<double>(to_first_checkpoint.count())));
      if (seen.empty()) return Ms::max();
      return seen.front() + Ms(static_cast<long long>(s * static_cast<double>(episode.count())));
    });
    code = w.code;
    if (!w.checkpoints.empty()) to_first_checkpoint = w.checkpoints.front();
    if (code == -SIGKILL) {
      ++kills;
      EXPECT_EQ(slurp(out), earlier) << "kill " << kills << " changed the earlier result";
      const int episode_now = checkpoint_episode(checkpoints);
      EXPECT_GE(episode_now, last_episode) << "a checkpoint went back";
      last_episode = episode_now;
      episodes.push_back(episode_now);
    } else {
      ASSERT_EQ(code, first.code) << slurp(log);
    }
  }
  EXPECT_EQ(kills, 8) << "every attempt but the last killed before it could finish";
  ASSERT_EQ(code, first.code);
  const nlohmann::json resumed = nlohmann::json::parse(slurp(out));
  const int resumed_from = resumed.at("method").at("details").at("resumed_from_episode").get<int>();
  std::printf("%d kills; checkpoint episode after each:", kills);
  for (int e : episodes) std::printf(" %d", e);
  std::printf("; the last run resumed after episode %d\n", resumed_from);
  EXPECT_GT(resumed_from, 0) << "the finishing run must have continued a checkpoint";
  EXPECT_EQ(result_of(out), result_of(straight));
  for (const auto& entry : fs::directory_iterator(dir.path()))  // no temporaries left beside the outputs
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
}

}  // namespace
}  // namespace lptn::td3
