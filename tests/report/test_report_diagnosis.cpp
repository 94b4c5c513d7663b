// The report of a real diagnosis (lptn diagnose --json, not a hand-written one) on plants whose
// physics the library lacks: the verdict on the model is the first thing on the page, a term of
// the dictionary gets an evidence plot the residual follows, and a drift gets its chart. Rendered
// by Debian's chromium headless.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lptn_testing/run_lptn.hpp"
#include "lptn_testing/temp_dir.hpp"
#include "lptn_testing/report_page.hpp"

namespace lptn::report {
namespace {

namespace fs = std::filesystem;
using testing::attribute;
using testing::element_chunk;
using testing::page_data;
using testing::run;
using testing::slurp;
using testing::TempDir;

struct Rendered {
  nlohmann::json diagnosis;  // as lptn diagnose --json wrote it
  nlohmann::json data;       // as the report embedded it
  std::string dom;           // after the page's script ran
};

// generate (with `plant`) -> calibrate -> diagnose --json -> report -> chromium, as a user runs them.
// The last two cycles are held out, as the diagnose suite's fixture holds them out.
Rendered diagnose_and_render(const TempDir& t, const std::string& generate) {
  const fs::path d = t.path();
  Rendered r;
  const auto g = run("generate --out " + (d / "data").string() + " " + generate, d);
  EXPECT_EQ(g.code, 0) << g.err;
  std::vector<std::string> cycles;
  for (const auto& f : fs::directory_iterator(d / "data"))
    if (f.path().extension() == ".csv") cycles.push_back(f.path().stem().string());
  std::sort(cycles.begin(), cycles.end());
  EXPECT_GE(cycles.size(), 4u);
  const std::string test_cycles = cycles[cycles.size() - 2] + "," + cycles.back();
  const auto c = run("calibrate --quiet --data " + (d / "data").string() + " --motor " + (d / "data/motor.toml").string() +
                         " --out " + (d / "cal.json").string() + " --test-cycles " + test_cycles, d);
  // 0, or 3 where the calibration has warnings (a drifted motor: its test error is far above its
  // training error); never failed.
  EXPECT_TRUE(c.code == 0 || c.code == 3) << c.code << c.err;
  const auto dg = run("diagnose --quiet --json --data " + (d / "data").string() + " --calibration " + (d / "cal.json").string(), d);
  EXPECT_EQ(dg.code, 0) << dg.err;
  r.diagnosis = nlohmann::json::parse(dg.out);
  std::ofstream(d / "diagnosis.json") << dg.out;
  const auto rep = run("report --data " + (d / "data").string() + " --calibration " + (d / "cal.json").string() +
                           " --diagnosis " + (d / "diagnosis.json").string() + " --out " + (d / "report.html").string(), d);
  EXPECT_EQ(rep.code, 0) << rep.err;
  r.data = page_data(slurp(d / "report.html"));
  r.dom = testing::dump_dom(d / "report.html", d / "chromium.log");
  EXPECT_NE(r.dom, "") << slurp(d / "chromium.log");
  EXPECT_NE(r.dom.find("data-rendered=\"true\""), std::string::npos) << "the page's script did not finish";
  EXPECT_EQ(testing::page_errors(r.dom), "") << "JavaScript errors on the page";
  return r;
}

// The least-squares slope of a sensor's mean residual over the signature's bins (bin centres).
double slope(const nlohmann::json& bins) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const auto& b : bins) {
    if (b["n"].get<double>() == 0 || b["mean"].is_null()) continue;
    const double x = (b["lo"].get<double>() + b["hi"].get<double>()) / 2, y = b["mean"].get<double>();
    n += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// The verdict box of that class, up to the end of the page's header it sits in.
std::string verdict_box(const std::string& dom, const std::string& cls) {
  const std::string chunk = element_chunk(dom, "data-verdict", cls);
  return chunk.substr(0, chunk.find("</header>"));
}

int points(const std::string& dom, const std::string& chart) {
  const std::string p = attribute(element_chunk(dom, "data-chart", chart), "data-points");
  return p.empty() ? -1 : std::stoi(p);
}

// An extra stator loss no library effect models (eddy currents, ~I^2 f^2): the verdict opens the
// page, names the term diagnose recommends and how to add it, and that term's evidence shows the
// stator's residual falling as the term's predicted change rises (slope near -1), the rotor's not.
// Without the recommendation, the box says what the stator residual's shape suggests instead.
TEST(ReportDiagnosis, AMissingTermOpensThePageAndItsEvidenceFollowsIt) {
  TempDir t;
  const Rendered r = diagnose_and_render(t, "--cycles 8 --seed 3 --plant eddy_loss --minutes-min 20 --minutes-max 25");
  ASSERT_FALSE(r.diagnosis["adequate"].get<bool>());
  const nlohmann::json* rec = nullptr;
  for (const auto& c : r.diagnosis["candidates"])
    if (c["recommended"].get<bool>()) rec = &c;
  ASSERT_NE(rec, nullptr) << r.diagnosis.dump();
  ASSERT_EQ((*rec)["kind"], "term");
  const std::string name = (*rec)["effect"];

  const std::string verdict = verdict_box(r.dom, "missing");
  ASSERT_NE(verdict, "") << "no verdict box at the top";
  EXPECT_LT(r.dom.find("data-verdict="), r.dom.find("id=\"compare\"")) << "the verdict is not above the charts";
  EXPECT_NE(verdict.find("Something is missing"), std::string::npos);
  EXPECT_NE(verdict.find("largest at"), std::string::npos) << "the verdict does not say where";
  EXPECT_NE(verdict.find("lptn calibrate --effect " + name), std::string::npos) << verdict.substr(0, 2000);

  const nlohmann::json* ev = nullptr;
  for (const auto& e : r.data["diagnosis"]["evidence"])
    if (e["effect"] == name) ev = &e;
  ASSERT_NE(ev, nullptr) << "no evidence for the recommended term";
  EXPECT_EQ((*ev)["most"], "stator");
  EXPECT_GT(points(r.dom, "evidence-" + name), 5);
  for (const auto& s : (*ev)["sensors"]) {
    const double k = slope(s["bins"]);
    std::printf("%s evidence, %s residual against the term's change: slope %.2f, spread %.1fx its noise\n",
                name.c_str(), s["sensor"].get<std::string>().c_str(), k, s["trend_over_noise"].get<double>());
    if (s["sensor"] == "stator") {
      EXPECT_LT(k, -0.5);
      EXPECT_GT(k, -1.5);
    }
  }
  EXPECT_EQ(element_chunk(verdict, "data-shape", "stator"), "") << "shape words beside a recommendation";

  // Where no candidate explains the residual, the box says what its shape suggests, per sensor that
  // is not adequate: the same diagnosis with its recommendation taken back (as one whose candidates
  // all failed would read), rendered again.
  const std::string words = r.diagnosis["sensors"]["stator"]["shape"]["words"];
  ASSERT_GT(words.size(), 60u) << "diagnose gave the failing stator no shape words";
  EXPECT_EQ(r.diagnosis["sensors"]["rotor"]["shape"]["words"], "") << "an adequate sensor is worded";
  nlohmann::json unexplained = r.diagnosis;
  for (auto& c : unexplained["candidates"]) c["recommended"] = false;
  const fs::path d = t.path();
  std::ofstream(d / "unexplained.json") << unexplained.dump();
  const auto rep = run("report --data " + (d / "data").string() + " --calibration " + (d / "cal.json").string() +
                           " --diagnosis " + (d / "unexplained.json").string() + " --out " + (d / "unexplained.html").string(), d);
  ASSERT_EQ(rep.code, 0) << rep.err;
  const std::string dom = testing::dump_dom(d / "unexplained.html", d / "chromium2.log");
  EXPECT_EQ(testing::page_errors(dom), "") << "JavaScript errors on the page";
  const std::string box = verdict_box(dom, "missing");
  ASSERT_NE(box, "") << "no verdict box at the top";
  EXPECT_EQ(box.find("lptn calibrate --effect"), std::string::npos) << "a recommendation shown";
  const std::string shape = element_chunk(box, "data-shape", "stator");
  ASSERT_NE(shape, "") << box.substr(0, 3000);
  // The page capitalises the first letter; then diagnose's words (their start: no HTML escapes).
  EXPECT_NE(shape.find(words.substr(1, 60)), std::string::npos) << shape.substr(0, 800);
  EXPECT_EQ(element_chunk(box, "data-shape", "rotor"), "");
}

// Cooling that weakens over the dump: the page opens on the drift, and its chart marks the cycles
// diagnose names, one point per cycle.
TEST(ReportDiagnosis, ADriftOpensThePageAndItsChartMarksTheDriftedCycles) {
  TempDir t;
  const Rendered r = diagnose_and_render(t, "--cycles 9 --seed 5 --plant cooling_fouling --minutes-min 20 --minutes-max 25");
  const auto& drift = r.diagnosis["drift"];
  ASSERT_TRUE(drift["found"].get<bool>()) << drift.dump();
  const std::string verdict = verdict_box(r.dom, "drift");
  ASSERT_NE(verdict, "") << "no drift verdict at the top";
  EXPECT_NE(verdict.find(drift["finding"].get<std::string>().substr(0, 40)), std::string::npos);
  EXPECT_EQ(verdict.find("lptn calibrate --effect"), std::string::npos) << "a drift is never an effect to add";
  EXPECT_EQ(points(r.dom, "drift"), static_cast<int>(drift["factors"].size()));
  EXPECT_EQ(attribute(element_chunk(r.dom, "data-chart", "drift"), "data-series"), "cooling factor|cooling factor (drifted)");
}

// A sensor fault opens the page above everything else, with what to inspect and the command that
// calibrates around it, never an effect to add; its chart marks the faulty cycles. The diagnosis is
// a real one of a small dump, with a sensor finding put into it as diagnose writes one
// (docs/diagnosis.md, "Sensor faults": finding it takes nine cycles of an hour, tested in
// tests/diagnose/test_sensor_faults.cpp).
TEST(ReportDiagnosis, ASensorFaultOpensThePageWithTheCommandThatCalibratesAroundIt) {
  TempDir t;
  const fs::path d = t.path();
  ASSERT_EQ(run("generate --out " + (d / "data").string() + " --cycles 4 --seed 61 --minutes-min 10 --minutes-max 12", d).code, 0);
  const std::string data = "--data " + (d / "data").string() + " --calibration " + (d / "cal.json").string();
  const auto c = run("calibrate --quiet --data " + (d / "data").string() + " --motor " + (d / "data/motor.toml").string() +
                         " --out " + (d / "cal.json").string() + " --test-cycles cycle_04_hilly", d);
  ASSERT_TRUE(c.code == 0 || c.code == 3) << c.err;
  const auto dg = run("diagnose --quiet --json " + data, d);
  ASSERT_EQ(dg.code, 0) << dg.err;
  nlohmann::json diagnosis = nlohmann::json::parse(dg.out);
  ASSERT_TRUE(diagnosis["sensor_faults"].is_array());
  ASSERT_FALSE(diagnosis["sensor_faults"].empty());
  EXPECT_EQ(diagnosis["format_version"], 2);
  {
    // A diagnosis from a newer lptn is refused by name, not misread.
    nlohmann::json newer = diagnosis;
    newer["format_version"] = 99;
    std::ofstream(d / "newer.json") << newer.dump();
    const auto r = run("report " + data + " --diagnosis " + (d / "newer.json").string() + " --out " +
                           (d / "newer.html").string(), d);
    EXPECT_NE(r.code, 0);
    EXPECT_NE(r.err.find("newer.json: format_version 99"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(d / "newer.html"));
    // One cut short: the file and the line, in one line.
    std::ofstream(d / "cut.json") << "{\n  \"candidates\": [\n";
    const auto cut = run("report " + data + " --diagnosis " + (d / "cut.json").string() + " --out " +
                             (d / "cut.html").string(), d);
    EXPECT_EQ(cut.code, 2);
    EXPECT_NE(cut.err.find((d / "cut.json").string() + ": not JSON (expected `lptn diagnose --json` output): line 3: "),
              std::string::npos) << cut.err;
    EXPECT_EQ(cut.err.find("json.exception"), std::string::npos) << cut.err;
    EXPECT_EQ(std::count(cut.err.begin(), cut.err.end(), '\n'), 1) << cut.err;
    EXPECT_FALSE(fs::exists(d / "cut.html"));
  }
  nlohmann::json& f = diagnosis["sensor_faults"][0];
  EXPECT_EQ(f["sensor"], "stator");
  EXPECT_FALSE(f["found"].get<bool>()) << "clean data";
  const std::string finding = "the stator sensor reads 3.0 K high from cycle_03_intercity on (cycles cycle_03_intercity .. "
                              "cycle_04_hilly; p = 0.0100 over 4000 orderings)";
  const std::string spec = "stator:offset:+3.00:cycle_03_intercity";
  f["found"] = true;
  f["shape"] = "offset";
  f["size_k"] = 3.0;
  f["cycles"] = {"cycle_03_intercity", "cycle_04_hilly"};
  f["finding"] = finding;
  f["calibrate"] = spec;
  std::ofstream(d / "diagnosis.json") << diagnosis.dump(2);
  const auto rep = run("report " + data + " --diagnosis " + (d / "diagnosis.json").string() + " --out " +
                           (d / "report.html").string(), d);
  ASSERT_EQ(rep.code, 0) << rep.err;
  const std::string dom = testing::dump_dom(d / "report.html", d / "chromium.log");
  ASSERT_NE(dom, "") << slurp(d / "chromium.log");
  EXPECT_EQ(testing::page_errors(dom), "") << "JavaScript errors on the page";
  const std::string verdict = verdict_box(dom, "sensor");
  ASSERT_NE(verdict, "") << "no sensor verdict at the top";
  EXPECT_LT(verdict.find("A sensor reads wrong"), verdict.find("adequate")) << "the fault is said first";
  EXPECT_NE(verdict.find(finding.substr(0, 60)), std::string::npos);
  EXPECT_NE(verdict.find("lptn calibrate --sensor-fault " + spec), std::string::npos);
  EXPECT_EQ(verdict.find("lptn calibrate --effect"), std::string::npos) << "a sensor fault is never an effect to add";
  EXPECT_EQ(points(dom, "sensor-stator"), static_cast<int>(f["offsets"].size()));
  EXPECT_EQ(attribute(element_chunk(dom, "data-chart", "sensor-stator"), "data-series"), "offset K|offset K (faulty)");
}

}  // namespace
}  // namespace lptn::report
