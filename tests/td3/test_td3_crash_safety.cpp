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

#include "../cli/temp_dir.hpp"

extern char** environ;

namespace lptn {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

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

// Waits for the child at most `limit`; kills it with SIGKILL at the limit. Returns its exit code,
// or -SIGKILL where it was killed.
int wait_or_kill(pid_t pid, std::chrono::milliseconds limit) {
  const auto until = std::chrono::steady_clock::now() + limit;
  int status = 0;
  for (;;) {
    const pid_t r = waitpid(pid, &status, WNOHANG);
    if (r == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
    if (std::chrono::steady_clock::now() >= until) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
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

TEST(Td3CrashSafety, KilledAtRandomMomentsAndResumedItEndsWhereAnUninterruptedRunEnds) {
  testing::TempDir dir;
  const fs::path data = dir.path() / "fleet", config = dir.path() / "small.toml";
  const fs::path log = dir.path() / "log.txt";
  ASSERT_EQ(std::system((std::string(LPTN_BINARY) + " generate --out " + data.string() +
                         " --cycles 3 --seed 4 --minutes-min 6 --minutes-max 8 > /dev/null 2>&1").c_str()), 0);
  // The paper's formulation on a budget that runs in seconds, with a checkpoint after every episode.
  std::ofstream(config) << "max_steps_per_episode = 3000\nrandom_episodes = 2\nupdates_per_episode = 400\n"
                           "checkpoint_every = 1\n[agent]\nhidden = 64\nbatch_size = 64\n";
  const auto args = [&](const std::string& out, const std::string& checkpoints) {
    return std::vector<std::string>{"calibrate", "--data", data.string(), "--motor", (data / "motor.toml").string(),
                                    "--method", "td3", "--config", config.string(), "--episodes", "14", "--seed", "3",
                                    "--out", out, "--checkpoint-dir", checkpoints, "--force", "--quiet"};
  };

  const fs::path straight = dir.path() / "straight.json";
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(wait_or_kill(spawn_lptn(args(straight.string(), (dir.path() / "straight.ckpt").string()), log),
                         std::chrono::minutes(5)), 0) << slurp(log);
  const auto run_ms = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0);
  std::printf("uninterrupted run: %lld ms\n", static_cast<long long>(run_ms.count()));

  // An earlier result in the output's place: no kill may touch it, only the finished run replace it.
  const fs::path out = dir.path() / "killed.json", checkpoints = dir.path() / "killed.ckpt";
  fs::copy_file(straight, out);
  std::ofstream(out, std::ios::app) << "\n";  // told apart from the final result
  const std::string earlier = slurp(out);

  // Random moments, the same ones on every run of the test: up to a third of a whole run, so that
  // every attempt is killed before it could finish and each resumes from where the last one got.
  std::mt19937 rng(20261123);
  std::uniform_real_distribution<double> share(0.02, 1.0 / 3);
  int kills = 0, code = -1, last_episode = 0;
  std::vector<int> episodes;
  for (int attempt = 0; attempt < 40 && code != 0; ++attempt) {
    std::vector<std::string> a = args(out.string(), checkpoints.string());
    if (fs::exists(checkpoints / "state.json")) a.push_back("--resume");
    // Six kills at least, and on until a checkpoint exists (a loaded machine may need longer: the
    // window widens with each kill).
    const bool kill_this_one = kills < 6 || (last_episode == 0 && kills < 20);
    const auto moment = std::chrono::milliseconds(
        static_cast<long long>(share(rng) * (1.0 + kills / 3.0) * static_cast<double>(run_ms.count())));
    code = wait_or_kill(spawn_lptn(a, log), kill_this_one ? moment : std::chrono::minutes(5));
    if (code == -SIGKILL) {
      ++kills;
      EXPECT_EQ(slurp(out), earlier) << "kill " << kills << " changed the earlier result";
      const int episode = checkpoint_episode(checkpoints);
      EXPECT_GE(episode, last_episode) << "a checkpoint went back";
      last_episode = episode;
      episodes.push_back(episode);
    } else {
      ASSERT_EQ(code, 0) << slurp(log);
    }
  }
  EXPECT_GE(kills, 6);
  ASSERT_EQ(code, 0);
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
}  // namespace lptn
