// The bad-input corpus: every directory here holds an input that tries to break lptn and, in
// case.json, what it must produce: the exit code, the message (exact, or lines that must appear)
// and, for a command that fails, no output at all (nothing half-written, no temporary left).
// Two inputs too big to keep in the repository are made here: a CSV and a CAN log with a 2 GB
// line (sparse files), which must be refused or skipped without being read whole.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lptn_testing/temp_dir.hpp"

namespace lptn::cli {
namespace {

namespace fs = std::filesystem;

const fs::path kCorpus = LPTN_TEST_DATA_DIR;

using testing::slurp;

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t at = 0; (at = s.find(from, at)) != std::string::npos; at += to.size()) s.replace(at, from.size(), to);
  return s;
}

std::string shell_quote(const std::string& s) {
  std::string q("'");
  q.append(replace_all(s, "'", "'\\''")).append("'");
  return q;
}

struct Outcome {
  int code;
  std::string out, err;
  long peak_rss_kb;  // of the largest child so far (getrusage), for the huge-line cases
};

Outcome run(const std::vector<std::string>& argv, const fs::path& scratch) {
  std::string cmd;
  for (const std::string& a : argv) cmd.append(cmd.empty() ? "" : " ").append(shell_quote(a));
  const fs::path out = scratch / "stdout.txt", err = scratch / "stderr.txt";
  cmd.append(" >").append(shell_quote(out)).append(" 2>").append(shell_quote(err));
  const int status = std::system(cmd.c_str());
  rusage usage{};
  getrusage(RUSAGE_CHILDREN, &usage);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err), usage.ru_maxrss};
}

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  return s;
}

std::vector<std::string> corpus_cases() {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(kCorpus))
    if (fs::exists(entry.path() / "case.json")) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

class BadInput : public ::testing::TestWithParam<std::string> {};

TEST_P(BadInput, ProducesItsErrorAndNothingHalfWritten) {
  const fs::path dir = kCorpus / GetParam();
  const nlohmann::json spec = nlohmann::json::parse(slurp(dir / "case.json"));
  SCOPED_TRACE(spec.at("why").get<std::string>());
  testing::TempDir scratch, out;
  const auto expand = [&](std::string s) {
    s = replace_all(s, "{case}", dir.string());
    s = replace_all(s, "{common}", (kCorpus / "common").string());
    return replace_all(s, "{out}", out.path().string());
  };
  std::vector<std::string> argv;
  if (spec.value("program", "lptn") == "lptn-dbc-codegen") {
    argv = {LPTN_DBC_CODEGEN};
  } else {
    argv = {LPTN_BINARY};
  }
  for (const auto& a : spec.at("run")) argv.push_back(expand(a.get<std::string>()));

  const Outcome r = run(argv, scratch.path());
  const int exit_code = spec.at("exit").get<int>();
  EXPECT_EQ(r.code, exit_code) << r.err;
  if (spec.contains("stderr")) {
    EXPECT_EQ(trimmed(r.err), expand(spec.at("stderr").get<std::string>()));
  }
  for (const auto& s : spec.value("stderr_contains", nlohmann::json::array()))
    EXPECT_NE(r.err.find(expand(s.get<std::string>())), std::string::npos) << expand(s.get<std::string>()) << "\nin\n" << r.err;
  for (const auto& s : spec.value("stdout_contains", nlohmann::json::array()))
    EXPECT_NE(r.out.find(expand(s.get<std::string>())), std::string::npos) << expand(s.get<std::string>()) << "\nin\n" << r.out;
  if (exit_code != 0) {
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
    for (const auto& entry : fs::directory_iterator(out.path())) ADD_FAILURE() << "left behind: " << entry.path();
  } else {
    for (const auto& entry : fs::recursive_directory_iterator(out.path()))
      EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
  }
}

INSTANTIATE_TEST_SUITE_P(Corpus, BadInput, ::testing::ValuesIn(corpus_cases()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           std::string name = param.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

// `head` followed by a 2 GiB run of NUL bytes with no line end, then `tail`; sparse, so it costs
// neither disk nor time to make.
fs::path with_huge_line(const fs::path& file, const std::string& head, const std::string& tail) {
  constexpr off_t kHuge = off_t{2} << 30;
  { std::ofstream(file, std::ios::binary) << head; }
  const int fd = ::open(file.c_str(), O_WRONLY);
  EXPECT_GE(fd, 0);
  EXPECT_EQ(::ftruncate(fd, static_cast<off_t>(head.size()) + kHuge), 0);
  EXPECT_EQ(::lseek(fd, 0, SEEK_END), static_cast<off_t>(head.size()) + kHuge);
  EXPECT_EQ(::write(fd, tail.data(), tail.size()), static_cast<ssize_t>(tail.size()));
  ::close(fd);
  return file;
}

constexpr long kMaxPeakRssKb = 256 * 1024;  // far below the line's 2 GiB

TEST(BadInputHugeLine, ACsvWithATwoGigabyteLineIsRefusedWithoutReadingItWhole) {
  testing::TempDir dir, scratch;
  const std::string csv = slurp(kCorpus / "common" / "cycle.csv");
  const std::string header = csv.substr(0, csv.find('\n') + 1);
  const fs::path file = with_huge_line(dir.path() / "huge.csv", header + "0.0,", "\n");
  const fs::path out = dir.path() / "simulation";
  const Outcome r = run({LPTN_BINARY, "simulate", "--data", file.string(), "--motor", (kCorpus / "common" / "motor.toml").string(),
                     "--out", out.string()}, scratch.path());
  EXPECT_EQ(r.code, 2);
  std::string expected("lptn: error: ");  // appended: GCC 12 warns falsely (-Wrestrict) on literal + string chains
  expected.append(file.string()).append(":2: line longer than 1 MiB (a fleet-dump row is a few hundred bytes): not a CSV, or a broken file");
  EXPECT_EQ(trimmed(r.err), expected);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_LT(r.peak_rss_kb, kMaxPeakRssKb);
  std::printf("peak RSS %ld kB\n", r.peak_rss_kb);
}

TEST(BadInputHugeLine, ACanLogWithATwoGigabyteLineLosesThatLineOnly) {
  testing::TempDir dir, scratch;
  const std::string log = slurp(kCorpus / "common" / "cycle.log");
  const std::size_t cut = log.find('\n', log.size() / 2) + 1;  // the huge line in the middle
  const int head_lines = static_cast<int>(std::count(log.begin(), log.begin() + static_cast<std::ptrdiff_t>(cut), '\n'));
  std::string tail("\n");  // the huge line's end, then the rest of the log
  tail.append(log, cut);
  const fs::path file = with_huge_line(dir.path() / "huge.log", log.substr(0, cut), tail);
  const fs::path out = dir.path() / "cycle.csv", reference = dir.path() / "reference.csv";
  const Outcome r = run({LPTN_BINARY, "convert", "--in", file.string(), "--out", out.string()}, scratch.path());
  EXPECT_EQ(r.code, 0) << r.err;
  std::string expected = file.string();
  expected.append(":").append(std::to_string(head_lines + 1)).append(": line longer than 512 bytes, not a candump line");
  EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  EXPECT_LT(r.peak_rss_kb, kMaxPeakRssKb);
  // Every other frame is kept: the same CSV as from the log without the line.
  ASSERT_EQ(run({LPTN_BINARY, "convert", "--in", (kCorpus / "common" / "cycle.log").string(), "--out", reference.string()},
                scratch.path()).code, 0);
  EXPECT_EQ(slurp(out), slurp(reference));
}

}  // namespace
}  // namespace lptn::cli
