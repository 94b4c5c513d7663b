// A fleet as a user runs it: lptn generate --fleet, calibrate --fleet, report --fleet (rendered by
// Debian's chromium headless) and export --fleet --motor-id; the weak motor, known only to the
// generator's truth.json, named on the page and by no other means.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "lptn_testing/run_lptn.hpp"
#include "lptn_testing/temp_dir.hpp"
#include "lptn_testing/report_page.hpp"

namespace lptn::report {
namespace {

namespace fs = std::filesystem;
using testing::attribute;
using testing::element_chunk;
using testing::run;
using testing::slurp;

TEST(ReportFleet, TheWeakMotorIsNamedOnTheFleetPageAndExportsAlone) {
  testing::TempDir t;
  const fs::path d = t.path();
  // The demo's fleet (scripts/demo.sh, step 9).
  const auto g = run("generate --fleet --motors 6 --cycles 2 --seed 5 --minutes-min 40 --minutes-max 50 --out " +
                         (d / "motors").string(), d);
  ASSERT_EQ(g.code, 0) << g.err;
  const nlohmann::json truth = nlohmann::json::parse(slurp(d / "motors/truth.json"));
  std::string weak;
  for (const auto& [id, m] : truth["motors"].items())
    if (m["weak"].get<bool>()) weak = id;
  ASSERT_FALSE(weak.empty());

  const auto c = run("calibrate --fleet " + (d / "motors").string() + " --motor " + (d / "motors/motor.toml").string() +
                         " --method lm --out " + (d / "fleet.json").string(), d);
  ASSERT_EQ(c.code, 0) << c.err;
  EXPECT_NE(c.out.find("OUTLIER"), std::string::npos) << c.out;
  const nlohmann::json fleet = nlohmann::json::parse(slurp(d / "fleet.json"));
  ASSERT_EQ(fleet["motors"].size(), 6u);
  for (const auto& [id, m] : fleet["motors"].items()) EXPECT_EQ(m["outlier"].get<bool>(), id == weak) << id;
  EXPECT_EQ(fleet["pooled"]["method"]["name"], "lm");

  const auto r = run("report --fleet " + (d / "fleet.json").string() + " --out " + (d / "fleet.html").string(), d);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string dom = testing::dump_dom(d / "fleet.html", d / "chromium.log");
  ASSERT_NE(dom, "") << slurp(d / "chromium.log");
  EXPECT_EQ(testing::page_errors(dom), "");
  const std::string chart = element_chunk(dom, "data-chart", "fleet");
  EXPECT_EQ(attribute(chart, "data-points"), "6");
  EXPECT_EQ(attribute(chart, "data-series"), "cooling factor|outlier");
  const std::string verdict = element_chunk(dom, "data-verdict", "fleet");
  EXPECT_NE(verdict.find("Outlier: " + weak + " cools "), std::string::npos) << verdict.substr(0, 400);
  EXPECT_NE(verdict.find("worse than the fleet's median motor"), std::string::npos) << verdict.substr(0, 400);
  const std::string table = element_chunk(dom, "data-table", "fleet");
  std::size_t rows = 0, outlier_rows = 0;
  for (std::size_t at = 0; (at = table.find("<tr", at)) != std::string::npos; ++at) ++rows;
  for (std::size_t at = 0; (at = table.find("<tr class=\"outlier\"", at)) != std::string::npos; ++at) ++outlier_rows;
  EXPECT_EQ(rows, 7u);  // the header and six motors
  EXPECT_EQ(outlier_rows, 1u);
  // A page of the fleet alone: the single-calibration sections are hidden, not drawn empty.
  EXPECT_NE(dom.find("id=\"compare\" style=\"display: none;\""), std::string::npos);

  const auto e = run("export --fleet " + (d / "fleet.json").string() + " --motor-id " + weak + " --out " +
                         (d / "weak.hpp").string(), d);
  ASSERT_EQ(e.code, 0) << e.err;
  const std::string header = slurp(d / "weak.hpp");
  EXPECT_NE(header.find("motor " + weak), std::string::npos);
  const auto unknown = run("export --fleet " + (d / "fleet.json").string() + " --motor-id motor_99 --out " +
                               (d / "none.hpp").string(), d);
  EXPECT_EQ(unknown.code, 2);
  EXPECT_NE(unknown.err.find("no motor 'motor_99' in the fleet (its motors: motor_01, "), std::string::npos) << unknown.err;
  EXPECT_FALSE(fs::exists(d / "none.hpp"));
  const auto td3 = run("calibrate --fleet " + (d / "motors").string() + " --motor " + (d / "motors/motor.toml").string() +
                           " --method td3 --out " + (d / "td3.json").string(), d);
  EXPECT_EQ(td3.code, 2);
  EXPECT_NE(td3.err.find("--fleet: only --method lm"), std::string::npos) << td3.err;
}

}  // namespace
}  // namespace lptn::report
