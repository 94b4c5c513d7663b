// `lptn export` as a user meets it: --help, the header written whole, no silent overwrite, and
// one-line errors with exit code 2.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "lptn_testing/sample_result.hpp"
#include "lptn_testing/temp_dir.hpp"

namespace lptn::exporter {
namespace {

struct Result {
  int code;
  std::string out, err;
};

using testing::slurp;

Result run(const std::string& args, const std::filesystem::path& scratch) {
  const auto out = scratch / "stdout.txt", err = scratch / "stderr.txt";
  const std::string cmd = std::string(LPTN_BINARY) + " " + args + " >" + out.string() + " 2>" + err.string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

// Only the header and the calibration: no temporaries left behind.
int files_in(const std::filesystem::path& dir) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().filename() != "stdout.txt" && e.path().filename() != "stderr.txt") ++n;
  return n;
}

class ExportCli : public ::testing::Test {
 protected:
  void SetUp() override {
    calibrate::CalibrationResult c = testing::sample_result();
    calibrate::save_calibration(c, with_actor_);
    c.has_actor = false;
    calibrate::save_calibration(c, without_actor_);
  }
  testing::TempDir t_;
  std::filesystem::path with_actor_ = t_.path() / "td3.json", without_actor_ = t_.path() / "lm.json";
  std::filesystem::path out_ = t_.path() / "thermal_calibration.hpp";
};

// A failed calibration: exit 2, one line naming the file and why, nothing written.
TEST_F(ExportCli, RefusesAFailedCalibration) {
  calibrate::CalibrationResult c = testing::sample_result();
  c.has_actor = false;
  c.status = calibrate::kStatusFailed;
  c.warnings = {{"not_converged", "the fit did not converge", {}}};
  const auto failed = t_.path() / "failed.json";
  calibrate::save_calibration(c, failed);
  const Result r = run("export --calibration " + failed.string() + " --out " + out_.string(), t_.path());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("failed.json: status 'failed', not exported: the fit did not converge"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out_));
}

// Warnings: each printed on a line of its own, the header written with them as comments.
TEST_F(ExportCli, PrintsEachWarning) {
  calibrate::CalibrationResult c = testing::sample_result();
  c.has_actor = false;
  c.status = calibrate::kStatusWarnings;
  c.warnings = {{"at_bound", "lambda_1s ended at its lower bound", {"lambda_1s"}},
                {"not_converged", "the fit did not converge", {}}};
  const auto warned = t_.path() / "warned.json";
  calibrate::save_calibration(c, warned);
  const Result r = run("export --calibration " + warned.string() + " --out " + out_.string(), t_.path());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(lines(r.err), 2) << r.err;
  EXPECT_NE(r.err.find("warning: warned.json: lambda_1s ended at its lower bound\n"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("warning: warned.json: the fit did not converge\n"), std::string::npos) << r.err;
  EXPECT_NE(slurp(out_).find("//   warning      at_bound: lambda_1s ended at its lower bound\n"), std::string::npos);
}

TEST_F(ExportCli, Help) {
  const Result r = run("export --help", t_.path());
  EXPECT_EQ(r.code, 0);
  for (const char* opt : {"--calibration", "--out", "--actor", "--force"}) EXPECT_NE(r.out.find(opt), std::string::npos) << opt;
}

TEST_F(ExportCli, WritesTheHeader) {
  const Result r = run("export --calibration " + with_actor_.string() + " --out " + out_.string() + " --actor", t_.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find(out_.string()), std::string::npos);  // says where the output went
  const std::string h = slurp(out_);
  EXPECT_NE(h.find("kSourceFile[] = \"td3.json\""), std::string::npos);
  EXPECT_NE(h.find("kActor{"), std::string::npos);
  EXPECT_EQ(files_in(t_.path()), 3);
}

TEST_F(ExportCli, RefusesToOverwriteWithoutForce) {
  std::ofstream(out_) << "// mine\n";
  const Result r = run("export --calibration " + without_actor_.string() + " --out " + out_.string(), t_.path());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "lptn: error: " + out_.string() + ": exists (use --force to replace it)\n");
  EXPECT_EQ(slurp(out_), "// mine\n");
  const Result f = run("export --force --calibration " + without_actor_.string() + " --out " + out_.string(), t_.path());
  EXPECT_EQ(f.code, 0) << f.err;
  EXPECT_NE(slurp(out_).find("kParams"), std::string::npos);
}

TEST_F(ExportCli, ActorWithoutActorIsBadInput) {
  const Result r = run("export --actor --calibration " + without_actor_.string() + " --out " + out_.string(), t_.path());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(lines(r.err), 1);
  EXPECT_NE(r.err.find("lm.json: --actor: this calibration has no actor"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out_));
  EXPECT_EQ(files_in(t_.path()), 2);
}

TEST_F(ExportCli, BadCalibrationIsBadInput) {
  std::string text = slurp(without_actor_);
  std::ofstream(without_actor_, std::ios::trunc) << text.substr(0, text.size() / 3);
  const Result r = run("export --calibration " + without_actor_.string() + " --out " + out_.string(), t_.path());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(lines(r.err), 1);
  EXPECT_EQ(r.err.rfind("lptn: error: " + without_actor_.string() + ": line ", 0), 0u) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out_));

  const Result m = run("export --calibration " + (t_.path() / "nope.json").string() + " --out " + out_.string(), t_.path());
  EXPECT_EQ(m.code, 2);
  EXPECT_NE(m.err.find("nope.json: no such file"), std::string::npos) << m.err;  // said before any output is looked at
}

}  // namespace
}  // namespace lptn::exporter
