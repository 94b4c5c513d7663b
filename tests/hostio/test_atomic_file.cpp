// Outputs appear whole or not at all; temporaries of writers killed outright are cleared by the
// next writer of the same target, and only those.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iterator>

#include "lptn_testing/temp_dir.hpp"
#include "hostio/atomic_file.hpp"

namespace lptn::hostio {
namespace {

namespace fs = std::filesystem;

using testing::slurp;

// A pid that certainly belongs to no running process: a child that has exited and been reaped.
pid_t dead_pid() {
  const pid_t pid = fork();
  if (pid == 0) _exit(0);
  waitpid(pid, nullptr, 0);
  return pid;
}

TEST(AtomicFile, ReplacesWholeAndLeavesNoTemporary) {
  testing::TempDir dir;
  const fs::path f = dir.path() / "out.json";
  hostio::write_file_atomically(f, "first");
  hostio::write_file_atomically(f, "second");
  EXPECT_EQ(slurp(f), "second");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path())) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST(AtomicFile, ClearsTheTemporariesOfDeadWritersOfTheSameTargetOnly) {
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

  hostio::write_file_atomically(f, "whole");
  EXPECT_EQ(slurp(f), "whole");
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_FALSE(fs::exists(stale_dir));
  EXPECT_TRUE(fs::exists(live));
  EXPECT_TRUE(fs::exists(other));
  EXPECT_TRUE(fs::exists(lookalike));
}

TEST(AtomicFile, DirectoryAppearsOnlyOnCommit) {
  testing::TempDir dir;
  const fs::path target = dir.path() / "sim";
  {
    hostio::AtomicDirectory d(target, false);
    std::ofstream(d.path() / "a.csv") << "x";
    EXPECT_FALSE(fs::exists(target));
  }  // not committed: nothing
  EXPECT_FALSE(fs::exists(target));
  hostio::AtomicDirectory d(target, false);
  std::ofstream(d.path() / "a.csv") << "y";
  d.commit();
  EXPECT_EQ(slurp(target / "a.csv"), "y");
}

// The streamed writer (the daemon's and the replay's outputs) is the same writer: whole on commit,
// nothing without, and it clears what a killed writer of the same file left.
TEST(AtomicFile, StreamedOutputAppearsOnlyOnCommitAndClearsDeadWritersTemporaries) {
  testing::TempDir dir;
  const fs::path f = dir.path() / "estimates.csv";
  const fs::path stale = dir.path() / (".estimates.csv.tmp-" + std::to_string(dead_pid()));
  std::ofstream(stale) << "half";
  {
    hostio::AtomicFile out;
    ASSERT_TRUE(out.open(f.string()));
    std::fputs("never committed\n", out.get());
    EXPECT_FALSE(fs::exists(stale)) << "a dead writer's temporary";
    EXPECT_FALSE(fs::exists(f));
  }
  EXPECT_FALSE(fs::exists(f));
  hostio::AtomicFile out;
  ASSERT_TRUE(out.open(f.string()));
  std::fputs("a,b\n1,2\n", out.get());
  EXPECT_FALSE(fs::exists(f)) << "not before commit";
  ASSERT_TRUE(out.commit());
  EXPECT_EQ(slurp(f), "a,b\n1,2\n");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path())) ++entries;
  EXPECT_EQ(entries, 1) << "no temporary left";
}

}  // namespace
}  // namespace lptn::hostio
