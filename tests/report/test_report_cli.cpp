// lptn report end to end: generated data with windage hidden in it (the rotor fails, the stator
// does not), LM calibrations without and with windage, a hand-written diagnosis, the report
// rendered by Debian's chromium headless (scripts run, charts drawn, no errors, a worst window's
// link clicked), and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lptn_testing/run_lptn.hpp"
#include "lptn_testing/temp_dir.hpp"
#include "dump.hpp"
#include "lptn_testing/report_page.hpp"

namespace lptn::report {
namespace {

namespace fs = std::filesystem;
using testing::run;
using testing::TempDir;

using testing::slurp;

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

std::size_t count_lines(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

// The dump (dump.hpp) is shared and only read: ctest makes it once (LPTN_REPORT_DUMP names it);
// run by hand, the suite makes its own. Each test writes into a directory of its own.
class ReportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (const char* made = std::getenv("LPTN_REPORT_DUMP")) {
      dump_ = made;
      return;
    }
    own_dump_ = new TempDir;
    dump_ = own_dump_->path();
    const std::string error = testing::make_report_dump(dump_);
    ASSERT_EQ(error, "");
  }
  static void TearDownTestSuite() {
    delete own_dump_;
    own_dump_ = nullptr;
  }
  void SetUp() override {
    ASSERT_TRUE(fs::exists(dump("cal/2-windage.json"))) << "no dump in " << dump_ << " (lptn_report_make_dump)";
  }
  static fs::path dump(const std::string& name) { return dump_ / name; }
  fs::path path(const std::string& name) const { return scratch_.path() / name; }
  const fs::path& cwd() const { return scratch_.path(); }
  static std::string base_args() {
    return "report --data " + dump("data").string() + " --calibration " + dump("cal/1-paper.json").string();
  }
  static fs::path dump_;
  static TempDir* own_dump_;
  TempDir scratch_;
};
fs::path ReportTest::dump_;
TempDir* ReportTest::own_dump_ = nullptr;

// Two candidates as `lptn diagnose --json` writes them, one key the report does not know.
const char* kDiagnosis = R"({"rmse_k": 0.52, "candidates": [
  {"effect": "airgap", "statistic": 41.3, "predicted_rmse_k": 0.45, "refit_rmse_k": 0.44, "significant": true, "p_value": 1e-9},
  {"effect": "windage", "statistic": 1.2, "predicted_rmse_k": 0.52, "refit_rmse_k": 0.52, "significant": false}]})";

using testing::attribute;
using testing::attributes;
using testing::chromium;
using testing::element_chunk;
using testing::page_data;
using testing::shell;

TEST_F(ReportTest, PageRendersInChromiumWithEveryChartDrawnAndNoErrors) {
  write(path("diagnosis.json"), kDiagnosis);
  const fs::path out = path("report.html");
  auto r = run(base_args() + " --diagnosis " + path("diagnosis.json").string() + " --out " + out.string(), cwd());
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(fs::exists(out));
  const std::string html = slurp(out);
  EXPECT_EQ(html.find("http://"), html.find("http://www.w3.org"));  // nothing to fetch (SVG namespaces aside)

  ASSERT_TRUE(fs::exists("/usr/bin/chromium")) << "run scripts/setup.sh report";
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
  // 4 per cycle; the opening sensor's autocorrelation and 4 cross-correlations (the other's are drawn
  // when chosen); 2 evidence; history.
  EXPECT_EQ(charts, 3u * 4 + 1 + 4 + 2 + 1);
  // The paper's model on this short windage dump is not ok (the rotor far from its noise, and the
  // fit may run into a bound): the page says so above everything drawn from it.
  const nlohmann::json meta = page_data(html)["meta"];
  ASSERT_NE(meta["status"], "ok");
  const std::string status = element_chunk(d, "data-note", "calibration-status");
  EXPECT_NE(status.find("Calibration status: " + dump("cal/1-paper.json").string() + ": status " +
                        meta["status"].get<std::string>() + " ("), std::string::npos) << status.substr(0, 300);
  EXPECT_NE(status.find("not_adequate"), std::string::npos) << status.substr(0, 300);
  EXPECT_NE(d.find("data-table=\"diagnosis\""), std::string::npos);

  // Where it fails: both sensors, and the page opens on the rotor, which the paper's model misses
  // (windage), not on the stator it fits to the noise.
  const nlohmann::json data = page_data(html);
  ASSERT_TRUE(data.is_object());
  const auto& sensors = data["failures"]["sensors"];
  ASSERT_EQ(sensors.size(), 2u);
  EXPECT_EQ(sensors[0]["sensor"], "stator");
  EXPECT_EQ(sensors[1]["sensor"], "rotor");
  EXPECT_EQ(data["failures"]["default_sensor"], "rotor");
  EXPECT_LT(sensors[0]["error_over_noise"].get<double>(), 2.0);  // the stator: its noise
  EXPECT_GT(sensors[1]["error_over_noise"].get<double>(), 5.0);  // the rotor: far more
  ASSERT_FALSE(sensors[1]["worst"].empty());
  EXPECT_GT(sensors[1]["worst"][0]["rmse_k"].get<double>(), 3 * sensors[0]["worst"][0]["rmse_k"].get<double>());
  const std::string rotor_panel = element_chunk(d, "data-sensor-panel", "rotor");
  ASSERT_NE(rotor_panel, "");
  EXPECT_EQ(attribute(rotor_panel, "style"), "") << "the rotor's panel is hidden";
  EXPECT_NE(rotor_panel.find("data-table=\"speed-torque\""), std::string::npos);
  EXPECT_NE(rotor_panel.find("data-table=\"band-temperature\""), std::string::npos);
  EXPECT_NE(rotor_panel.find("rotor (measured)"), std::string::npos);
  EXPECT_EQ(attributes(rotor_panel, "data-sensor").size(), sensors[1]["worst"].size());  // one link per window
  EXPECT_NE(rotor_panel.find("data-chart=\"acf-rotor\""), std::string::npos);
  EXPECT_NE(element_chunk(d, "data-sensor-tab", "stator"), "") << "no way to the stator's panel";

  // Evidence: every sensor's residual against the signature.
  for (const auto& ev : data["diagnosis"]["evidence"]) {
    EXPECT_EQ(ev["sensors"].size(), 2u) << ev["effect"];
    EXPECT_EQ(attribute(element_chunk(d, "data-chart", "evidence-" + ev["effect"].get<std::string>()), "data-series"),
              "stator winding mean residual K|rotor mean residual K");
  }

  // History: both calibrations, every sensor's train and test error and the combined figure; the
  // rotor's test error falls when windage is added.
  const std::string history_chart = element_chunk(d, "data-chart", "history");
  EXPECT_EQ(attribute(history_chart, "data-points"), "2");
  EXPECT_EQ(attribute(history_chart, "data-series"),
            "train RMSE stator K|test RMSE stator K|train RMSE rotor K|test RMSE rotor K|"
            "train RMSE combined K|test RMSE combined K");
  const auto& runs = data["history"]["runs"];
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0]["file"], "1-paper.json");
  EXPECT_EQ(runs[1]["file"], "2-windage.json");
  EXPECT_GT(runs[0]["test_rmse_rotor_k"].get<double>(), 3 * runs[1]["test_rmse_rotor_k"].get<double>());
  // Pooled by samples: between the two sensors' figures.
  for (const std::string side : {"train", "test"}) {
    const double st = runs[0][side + "_rmse_stator_k"], ro = runs[0][side + "_rmse_rotor_k"],
                 co = runs[0][side + "_rmse_combined_k"];
    EXPECT_GT(co, std::min(st, ro)) << side;
    EXPECT_LT(co, std::max(st, ro)) << side;
  }

  // Kept beside the test binary for a person to look at.
  const fs::path shot = LPTN_REPORT_SCREENSHOT;
  fs::remove(shot);
  TempDir profile2;
  EXPECT_EQ(shell(chromium(profile2.path()) + "--virtual-time-budget=10000 --window-size=1400,3000 --screenshot=" +
                  shot.string() + " file://" + out.string() + " >" + path("chromium.log").string() + " 2>&1"), 0);
  EXPECT_TRUE(fs::exists(shot));
}

// A reader clicks the rotor's worst window: the charts of its cycle show that window and the page
// is there. The script that clicks is added to a copy of the page, after the page's own.
TEST_F(ReportTest, ClickingTheRotorsWorstWindowZoomsItsCycleToIt) {
  const fs::path out = path("click.html");
  auto r = run(base_args() + " --out " + out.string(), cwd());
  ASSERT_EQ(r.code, 0) << r.err;
  std::string html = slurp(out);
  const std::size_t body_end = html.rfind("</body>");
  ASSERT_NE(body_end, std::string::npos);
  html.insert(body_end, R"(<script>
(function () {
  var result = document.createElement('div');
  result.id = 'click-result';
  var link = document.querySelector('[data-sensor-panel="rotor"] a[data-zoom]');
  if (link) {
    var block = document.getElementById('cycle-' + link.getAttribute('data-zoom'));
    result.setAttribute('data-before', block.querySelector('[data-chart="residual"]').getAttribute('data-x-range'));
    link.click();
    ['data-zoom', 'data-start', 'data-end'].forEach(function (a) { result.setAttribute(a, link.getAttribute(a)); });
    result.setAttribute('data-top', String(Math.round(block.getBoundingClientRect().top)));
  }
  document.body.appendChild(result);
})();
</script>)");
  const fs::path clicked = path("clicked.html");
  write(clicked, html);
  TempDir profile;
  const fs::path dom = path("clicked-dom.html");
  ASSERT_EQ(shell(chromium(profile.path()) + "--virtual-time-budget=10000 --dump-dom file://" + clicked.string() + " >" +
                  dom.string() + " 2>" + path("chromium.log").string()), 0) << slurp(path("chromium.log"));
  const std::string d = slurp(dom);
  ASSERT_NE(d.find("data-rendered=\"true\""), std::string::npos);
  const std::size_t at = d.find("id=\"click-result\"");
  ASSERT_NE(at, std::string::npos);
  const std::string result = d.substr(at, d.find('>', at) - at);
  const std::string cycle = attribute(result, "data-zoom");
  ASSERT_NE(cycle, "") << "no link in the rotor's worst windows";
  const double start = std::stod(attribute(result, "data-start")), end = std::stod(attribute(result, "data-end"));
  EXPECT_NEAR(end - start, 300, 1);  // a 5-minute window
  char expected[64];
  std::snprintf(expected, sizeof expected, "%.1f,%.1f", start, end);
  EXPECT_NE(attribute(result, "data-before"), "");
  EXPECT_NE(attribute(result, "data-before"), expected) << "the chart showed the window before the click";
  // Every chart of that cycle (temperature, residual, drive, cooling) now shows the window.
  std::string block = element_chunk(d, "data-cycle", cycle);
  block = block.substr(0, block.find("<section id=\"failures\""));  // the last cycle's block ends with Compare
  const auto ranges = attributes(block, "data-x-range");
  EXPECT_EQ(ranges.size(), 4u);
  for (const auto& range : ranges) EXPECT_EQ(range, expected);
  // The residual chart there carries the rotor's residual, the failure the window was chosen for.
  EXPECT_NE(attribute(element_chunk(block, "data-chart", "residual"), "data-series").find("rotor residual"), std::string::npos);
  EXPECT_LE(std::abs(std::stoi(attribute(result, "data-top"))), 2) << "the page did not scroll to the cycle";
}

TEST_F(ReportTest, WithoutDiagnosisSaysHowToGetOne) {
  const fs::path out = path("plain.html");
  auto r = run(base_args() + " --out " + out.string(), cwd());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(slurp(out).find("\"diagnosis\":null"), std::string::npos);
}

TEST_F(ReportTest, RefusesToReplaceWithoutForce) {
  const fs::path out = path("exists.html");
  write(out, "keep");
  auto r = run(base_args() + " --out " + out.string(), cwd());
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
  expect_bad_input("report --data " + dump("data").string() + " --calibration " + path("nope.json").string(),
                   path("bad1/report.html"), "nope.json");
}

TEST_F(ReportTest, DiagnosisThatIsNotJsonIsBadInput) {
  fs::create_directories(path("bad2"));
  write(path("bad2/diagnosis.txt"), "effect statistic\nairgap 41.3\n");
  expect_bad_input(base_args() + " --diagnosis " + path("bad2/diagnosis.txt").string(), path("bad2/report.html"),
                   "diagnosis.txt: not JSON");
}

}  // namespace
}  // namespace lptn::report
