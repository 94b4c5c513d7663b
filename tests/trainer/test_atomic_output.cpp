// Outputs appear whole or not at all; temporaries of writers killed outright are cleared by the
// next writer of the same target, and only those.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <iterator>

#include "../cli/temp_dir.hpp"
#include "trainer/io/atomic_output.hpp"

namespace lptn {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// A pid that certainly belongs to no running process: a child that has exited and been reaped.
pid_t dead_pid() {
  const pid_t pid = fork();
  if (pid == 0) _exit(0);
  waitpid(pid, nullptr, 0);
  return pid;
}

TEST(AtomicOutput, ReplacesWholeAndLeavesNoTemporary) {
  testing::TempDir dir;
  const fs::path f = dir.path() / "out.json";
  write_file_atomically(f, "first");
  write_file_atomically(f, "second");
  EXPECT_EQ(slurp(f), "second");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path())) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST(AtomicOutput, ClearsTheTemporariesOfDeadWritersOfTheSameTargetOnly) {
  testing::TempDir dir;
  const fs::path f = dir.path() / "state.json";
  const std::string dead = std::to_string(dead_pid()), alive = std::to_string(::getppid());
  const fs::path stale = dir.path() / (".state.json.tmp-" + dead);
  const fs::path stale_dir = dir.path() / (".state.json.tmp-" + dead + ".old");
  const fs::path live = dir.path() / (".state.json.tmp-" + alive);             // a writer still running
  const fs::path other = dir.path() / (".agent.bin.tmp-" + dead);              // another target's
  const fs::path lookalike = dir.path() / (".state.json.tmp-" + dead + "x");   // not a temporary of ours
  for (const fs::path& p : {stale, live, other, lookalike}) std::ofstream(p) << "half";
  fs::create_directories(stale_dir / "inner");

  write_file_atomically(f, "whole");
  EXPECT_EQ(slurp(f), "whole");
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_FALSE(fs::exists(stale_dir));
  EXPECT_TRUE(fs::exists(live));
  EXPECT_TRUE(fs::exists(other));
  EXPECT_TRUE(fs::exists(lookalike));
}

TEST(AtomicOutput, DirectoryAppearsOnlyOnCommit) {
  testing::TempDir dir;
  const fs::path target = dir.path() / "sim";
  {
    AtomicDirectory d(target, false);
    std::ofstream(d.path() / "a.csv") << "x";
    EXPECT_FALSE(fs::exists(target));
  }  // not committed: nothing
  EXPECT_FALSE(fs::exists(target));
  AtomicDirectory d(target, false);
  std::ofstream(d.path() / "a.csv") << "y";
  d.commit();
  EXPECT_EQ(slurp(target / "a.csv"), "y");
}

}  // namespace
}  // namespace lptn
