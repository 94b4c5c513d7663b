// lptn report end to end: generated data, an LM calibration, a hand-written diagnosis, the report
// rendered by Debian's chromium headless (scripts run, charts drawn, no errors), and bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>

#include "../cli/run_lptn.hpp"
#include "../cli/temp_dir.hpp"

namespace lptn {
namespace {

namespace fs = std::filesystem;
using testing::run;
using testing::TempDir;

using testing::slurp;

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

std::size_t count_lines(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

// One generated dump and its calibration for every test of the suite (calibrating takes seconds).
class ReportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    const fs::path d = dir_->path();
    fs::create_directories(d / "cal");
    auto gen = run("generate --out " + (d / "data").string() + " --cycles 3 --seed 3 --minutes-min 15 --minutes-max 20", d);
    ASSERT_EQ(gen.code, 0) << gen.err;
    auto cal = run("calibrate --data " + (d / "data").string() + " --motor " + (d / "data" / "motor.toml").string() +
                       " --method lm --out " + (d / "cal" / "calibration.json").string(), d);
    ASSERT_EQ(cal.code, 0) << cal.err;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path path(const std::string& name) { return dir_->path() / name; }
  static std::string base_args() {
    return "report --data " + path("data").string() + " --calibration " + path("cal/calibration.json").string();
  }
  static TempDir* dir_;
};
TempDir* ReportTest::dir_ = nullptr;

// Two candidates as `lptn diagnose --json` writes them, one key the report does not know.
const char* kDiagnosis = R"({"rmse_k": 0.52, "candidates": [
  {"effect": "airgap", "statistic": 41.3, "predicted_rmse_k": 0.45, "refit_rmse_k": 0.44, "significant": true, "p_value": 1e-9},
  {"effect": "windage", "statistic": 1.2, "predicted_rmse_k": 0.52, "refit_rmse_k": 0.52, "significant": false}]})";

// chromium headless as root; a fresh profile, nothing fetched in the background.
std::string chromium(const fs::path& profile) {
  return "/usr/bin/chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
         "--disable-background-networking --disable-component-update --disable-sync --user-data-dir=" +
         profile.string() + " ";
}

int shell(const std::string& cmd) { return std::system(cmd.c_str()); }

TEST_F(ReportTest, PageRendersInChromiumWithEveryChartDrawnAndNoErrors) {
  write(path("cal/diagnosis.json"), kDiagnosis);
  const fs::path out = path("report.html");
  auto r = run(base_args() + " --diagnosis " + path("cal/diagnosis.json").string() + " --out " + out.string(), dir_->path());
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(fs::exists(out));
  const std::string html = slurp(out);
  EXPECT_EQ(html.find("http://"), html.find("http://www.w3.org"));  // nothing to fetch (SVG namespaces aside)

  ASSERT_TRUE(fs::exists("/usr/bin/chromium")) << "run tools/setup.sh report";
  TempDir profile;
  const fs::path dom = path("dom.html");
  ASSERT_EQ(shell(chromium(profile.path()) + "--virtual-time-budget=10000 --dump-dom file://" + out.string() + " >" +
                  dom.string() + " 2>" + path("chromium.log").string()), 0) << slurp(path("chromium.log"));
  const std::string d = slurp(dom);
  ASSERT_NE(d.find("data-rendered=\"true\""), std::string::npos) << "the page's script did not finish";
  const std::regex errors(R"(<div id="errors"[^>]*>([\s\S]*?)</div>\s*<header)");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(d, m, errors));
  EXPECT_EQ(m[1].str(), "") << "JavaScript errors on the page";

  // Every chart: points to draw and a canvas drawn into its container.
  std::size_t charts = 0;
  for (std::size_t at = d.find("data-chart=\""); at != std::string::npos; ++charts) {
    const std::size_t next = d.find("data-chart=\"", at + 1);
    const std::string chunk = d.substr(at, next == std::string::npos ? std::string::npos : next - at);
    const std::string name = chunk.substr(12, chunk.find('"', 12) - 12);
    std::smatch pm;
    ASSERT_TRUE(std::regex_search(chunk, pm, std::regex(R"re(data-points="(\d+)")re"))) << name;
    EXPECT_GT(std::stoul(pm[1].str()), 0u) << name;
    EXPECT_NE(chunk.find("<canvas"), std::string::npos) << name << " has no canvas";
    at = next;
  }
  EXPECT_EQ(charts, 3u * 4 + 1 + 4 + 2 + 1);  // 4 per cycle, autocorrelation, 4 cross, 2 evidence, history
  EXPECT_NE(d.find("data-table=\"diagnosis\""), std::string::npos);

  // Kept beside the test binary for a person to look at.
  const fs::path shot = LPTN_REPORT_SCREENSHOT;
  fs::remove(shot);
  TempDir profile2;
  EXPECT_EQ(shell(chromium(profile2.path()) + "--virtual-time-budget=10000 --window-size=1400,3000 --screenshot=" +
                  shot.string() + " file://" + out.string() + " >" + path("chromium.log").string() + " 2>&1"), 0);
  EXPECT_TRUE(fs::exists(shot));
}

TEST_F(ReportTest, WithoutDiagnosisSaysHowToGetOne) {
  const fs::path out = path("plain.html");
  auto r = run(base_args() + " --out " + out.string(), dir_->path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(slurp(out).find("\"diagnosis\":null"), std::string::npos);
}

TEST_F(ReportTest, RefusesToReplaceWithoutForce) {
  const fs::path out = path("exists.html");
  write(out, "keep");
  auto r = run(base_args() + " --out " + out.string(), dir_->path());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(slurp(out), "keep");
}

// Bad input: one line, exit 2, and neither the report nor a temporary left behind.
void expect_bad_input(const std::string& args, const fs::path& out, const std::string& mentions) {
  TempDir scratch;
  auto r = run(args + " --out " + out.string(), scratch.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find(mentions), std::string::npos) << r.err;
  for (const auto& f : fs::directory_iterator(out.parent_path()))
    EXPECT_EQ(f.path().filename().string().find(out.filename().string()), std::string::npos) << f.path();
}

TEST_F(ReportTest, MissingCalibrationIsBadInput) {
  fs::create_directories(path("bad1"));
  expect_bad_input("report --data " + path("data").string() + " --calibration " + path("nope.json").string(),
                   path("bad1/report.html"), "nope.json");
}

TEST_F(ReportTest, DiagnosisThatIsNotJsonIsBadInput) {
  fs::create_directories(path("bad2"));
  write(path("bad2/diagnosis.txt"), "effect statistic\nairgap 41.3\n");
  expect_bad_input(base_args() + " --diagnosis " + path("bad2/diagnosis.txt").string(), path("bad2/report.html"),
                   "diagnosis.txt: not JSON");
}

}  // namespace
}  // namespace lptn
