// Change indication, as PX4 does it: committed inputs, committed outputs, and this test runs the
// commands fresh and diffs every number. The golden tests in tests/replay hold implementations
// equal to each other, so a retuned gate or process noise, or an LM that lands elsewhere, passes
// them; here any such change fails, and the test writes the fresh outputs over the committed ones
// (tests/change_indication/expected/), so that the change is in `git diff` for review: commit it
// if it was intended, `git checkout` the files if not. The commands exist here only;
// scripts/update-change-indication.sh builds lptn and runs this test.
//
// Tolerance: |fresh - expected| <= 1e-9 * max(1, |fresh|, |expected|), i.e. absolute 1e-9 for
// values up to 1 and relative 1e-9 beyond. The same build on the same machine reproduces these
// files bit for bit; the slack is for another compiler or CPU (contraction into FMA, another
// libm), which moves results by ~1e-15 relative, far below the smallest change a retune makes.
// Relative above 1 because the values span 1e-3 (standard deviations) to 1e4 (sample counts);
// absolute below 1 because a relative bound near zero (a bias, an innovation) means nothing.
// A file is rewritten only where a value differs beyond that: a rounding in the last bits on
// another machine leaves the committed file alone.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "lptn_testing/temp_dir.hpp"

namespace lptn::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kHere = LPTN_TEST_DATA_DIR;
const fs::path kCalibration = fs::path(LPTN_SOURCE_DIR) / "firmware/calibration/default_calibration.json";
const fs::path kLog = kHere / "input/cycle.log";
const fs::path kFleet = kHere / "input/fleet";
constexpr double kTolerance = 1e-9;
// The replay's CSV keeps every 10th tick (the script's awk does the same): 1 s apart, enough to
// see any change in the estimator's dynamics, a tenth of the size.
constexpr std::size_t kEvery = 10;
constexpr std::size_t kShown = 20;  // mismatches spelled out; the rest are counted
const char* const kRegenerate =
    "the fresh output was written over the committed file: if the change is intended, commit it (git diff "
    "tests/change_indication shows every number that moved); if not, git checkout tests/change_indication/expected";

using testing::slurp;

struct Outcome {
  int code;
  std::string err;
};

Outcome run(const std::string& args, const fs::path& scratch) {
  const fs::path err = scratch / "stderr.txt";
  const std::string cmd = std::string(LPTN_BINARY) + " " + args + " >" + (scratch / "stdout.txt").string() + " 2>" +
                          err.string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(err)};
}

bool close_enough(double a, double b) {
  return std::abs(a - b) <= kTolerance * std::max({1.0, std::abs(a), std::abs(b)});
}

// A whole cell as a number; false for text and empty cells (compared as text, exactly).
bool as_number(const std::string& cell, double& v) {
  if (cell.empty()) return false;
  char* end = nullptr;
  v = std::strtod(cell.c_str(), &end);
  return end == cell.c_str() + cell.size() && std::isfinite(v);
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream row(line);
  for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();  // getline drops a trailing empty cell
  return cells;
}

// Mismatches of one comparison, each a line a reviewer can act on.
struct Diff {
  std::vector<std::string> lines;
  std::size_t count = 0;
  void add(const std::string& what) {
    if (count++ < kShown) lines.push_back(what);
  }
  std::string report(const std::string& file) const {
    std::string s = file + ": " + std::to_string(count) + " mismatch(es)\n";
    for (const auto& l : lines) s += "  " + l + "\n";
    if (count > lines.size()) s += "  ... and " + std::to_string(count - lines.size()) + " more\n";
    return s + kRegenerate;
  }
};

// The header and every kEvery-th tick of a replay's CSV: what expected/ keeps of it.
std::string decimated(const std::string& csv) {
  std::istringstream in(csv);
  std::string line, out;
  for (std::size_t n = 0; std::getline(in, line); ++n)
    if (n == 0 || (n - 1) % kEvery == 0) out += line + '\n';
  return out;
}

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

// `fresh` is the replay's full CSV; `expected` its committed decimation.
Diff diff_replay_csv(const std::string& fresh, const std::string& expected) {
  Diff d;
  std::istringstream f(fresh), e(expected);
  std::string fl, el;
  std::getline(f, fl);
  std::getline(e, el);
  if (fl != el) d.add("header: expected '" + el + "', got '" + fl + "'");
  const std::vector<std::string> names = split_csv(el);
  std::size_t tick = 0, row = 0;
  bool more_fresh = true;
  for (;; ++tick) {
    more_fresh = static_cast<bool>(std::getline(f, fl));
    if (!more_fresh) break;
    if (tick % kEvery != 0) continue;
    ++row;
    if (!std::getline(e, el)) {
      d.add("row " + std::to_string(row) + " (tick " + std::to_string(tick) + "): fresh output has it, expected file ends");
      continue;
    }
    const std::vector<std::string> fc = split_csv(fl), ec = split_csv(el);
    if (fc.size() != ec.size()) {
      d.add("row " + std::to_string(row) + " (tick " + std::to_string(tick) + "): " + std::to_string(ec.size()) +
            " cells expected, " + std::to_string(fc.size()) + " fresh");
      continue;
    }
    for (std::size_t i = 0; i < ec.size(); ++i) {
      double a = 0, b = 0;
      const bool same = as_number(ec[i], a) && as_number(fc[i], b) ? close_enough(a, b) : ec[i] == fc[i];
      if (!same)
        d.add("row " + std::to_string(row) + " (tick " + std::to_string(tick) + ", time_s " + ec[0] + "), column " +
              (i < names.size() ? names[i] : std::to_string(i)) + ": expected '" + ec[i] + "', got '" + fc[i] + "'");
    }
  }
  for (std::size_t extra = row + 1; std::getline(e, el); ++extra)
    d.add("row " + std::to_string(extra) + ": expected file has it, fresh output ends (tick " + std::to_string(tick) + ")");
  return d;
}

// The deterministic part of a calibration.json: parameters with values and standard errors, the
// flagged correlations, the split, LM's iterations, final cost and fitted initial offsets, the
// metrics. Not timestamps, wall times, paths, hashes or Ceres' termination text. Written in this
// order (ordered_json), every double in its shortest round-trip form.
nlohmann::ordered_json deterministic_part(const nlohmann::ordered_json& cal) {
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  nlohmann::ordered_json params = nlohmann::ordered_json::array();
  for (const nlohmann::ordered_json& p : cal.at("parameters"))
    params.push_back({{"name", p.at("name")},
                      {"unit", p.at("unit")},
                      {"calibrated", p.at("calibrated")},
                      {"value", p.at("value")},
                      {"std_error", p.at("std_error")}});
  out["parameters"] = params;
  out["correlated"] = cal.at("correlated");
  out["split"] = cal.at("data").at("split");
  const json& details = cal.at("method").at("details");
  out["method"] = {{"name", cal.at("method").at("name")},
                   {"iterations", details.at("iterations")},
                   {"converged", details.at("converged")},
                   {"final_cost_k2", details.at("final_cost_k2")},
                   {"initial_offsets", details.at("initial_offsets")}};
  out["metrics"] = cal.at("metrics");
  return out;
}

// An array element's name in a path: its "name" or "cycle" where it has one (parameters[lambda_1s]
// reads better than parameters[0] and survives a reordering), else its index.
std::string element(const json& v, std::size_t i) {
  for (const char* key : {"name", "cycle"})
    if (v.is_object() && v.contains(key) && v.at(key).is_string()) return v.at(key).get<std::string>();
  return std::to_string(i);
}

void diff_json(const json& fresh, const json& expected, const std::string& path, Diff& d) {
  const auto where = path.empty() ? std::string("(root)") : path;
  if (expected.is_number() && fresh.is_number()) {
    const double a = expected.get<double>(), b = fresh.get<double>();
    if (!close_enough(a, b)) d.add(where + ": expected " + expected.dump() + ", got " + fresh.dump());
  } else if (expected.is_object() && fresh.is_object()) {
    for (const auto& [k, v] : expected.items()) {
      const std::string sub = path.empty() ? k : path + "." + k;
      if (!fresh.contains(k))
        d.add(sub + ": expected " + v.dump() + ", missing in the fresh output");
      else
        diff_json(fresh.at(k), v, sub, d);
    }
    for (const auto& [k, v] : fresh.items())
      if (!expected.contains(k)) d.add((path.empty() ? k : path + "." + k) + ": not expected, got " + v.dump());
  } else if (expected.is_array() && fresh.is_array()) {
    const std::size_t n = std::max(expected.size(), fresh.size());
    for (std::size_t i = 0; i < n; ++i) {
      const json& one = i < expected.size() ? expected[i] : fresh[i];
      const std::string sub = path + "[" + element(one, i) + "]";
      if (i >= fresh.size())
        d.add(sub + ": expected " + expected[i].dump() + ", missing in the fresh output");
      else if (i >= expected.size())
        d.add(sub + ": not expected, got " + fresh[i].dump());
      else
        diff_json(fresh[i], expected[i], sub, d);
    }
  } else if (expected != fresh) {  // strings, booleans, null, or a change of type: exactly
    d.add(where + ": expected " + expected.dump() + ", got " + fresh.dump());
  }
}

// ---- the comparison itself can fail: a change of a part in a billion shows, a rounding does not

TEST(ChangeIndicationDiff, KeepsTheHeaderAndEveryTenthTick) {
  std::string csv = "time_s,est_c\n";
  for (int k = 0; k < 25; ++k) csv += std::to_string(k) + ",1\n";
  EXPECT_EQ(decimated(csv), "time_s,est_c\n0,1\n10,1\n20,1\n");
  EXPECT_EQ(diff_replay_csv(csv, decimated(csv)).count, 0u) << "the comparison reads what decimated() keeps";
}

TEST(ChangeIndicationDiff, SeesAChangeAboveOnePartInABillionAndNotBelow) {
  const std::string header = "time_s,est_c,mode\n";
  std::string rows;
  for (int k = 0; k < 25; ++k) rows += std::to_string(k) + ".000000,150.000000,1\n";
  std::string expected = header;
  for (int k = 0; k < 25; k += 10) expected += std::to_string(k) + ".000000,150.000000,1\n";
  EXPECT_EQ(diff_replay_csv(header + rows, expected).count, 0u);

  std::string moved = expected;  // row 2 (tick 10) 1e-6 K hotter: what the CSV's last digit is
  moved.replace(moved.find("150.000000", moved.find("10.000000")), 10, "150.000001");
  const Diff d = diff_replay_csv(header + rows, moved);
  ASSERT_EQ(d.count, 1u);
  EXPECT_NE(d.lines[0].find("row 2 (tick 10"), std::string::npos) << d.lines[0];
  EXPECT_NE(d.lines[0].find("column est_c: expected '150.000001', got '150.000000'"), std::string::npos) << d.lines[0];
  EXPECT_NE(d.report("x.csv").find("git diff tests/change_indication"), std::string::npos);

  std::string text = expected;  // a status that is not a number is compared as text
  text.replace(text.rfind(",1\n"), 3, ",2\n");
  EXPECT_EQ(diff_replay_csv(header + rows, text).count, 1u);
  EXPECT_EQ(diff_replay_csv(header + rows, expected + "30.000000,150.000000,1\n").count, 1u) << "a row short";

  const json a = {{"parameters", {{{"name", "lambda_1s"}, {"value", 24.0}, {"std_error", nullptr}}}}};
  json b = a;
  b["parameters"][0]["value"] = 24.0 * (1 + 1e-12);
  Diff none;
  diff_json(b, a, "", none);
  EXPECT_EQ(none.count, 0u) << "a rounding in the last bits is not a change";
  b["parameters"][0]["value"] = 24.0 * (1 + 1e-8);
  b["parameters"][0]["std_error"] = 0.1;
  Diff two;
  diff_json(b, a, "", two);
  ASSERT_EQ(two.count, 2u);
  const std::string report = two.report("calibration_lm.json");  // in key order: std_error first
  EXPECT_NE(report.find("parameters[lambda_1s].value: expected 24.0, got 24.00000024"), std::string::npos) << report;
  EXPECT_NE(report.find("parameters[lambda_1s].std_error: expected null, got 0.1"), std::string::npos) << report;
}

// ---- the committed outputs against fresh runs of the same commands

class ChangeIndication : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { dir_ = new testing::TempDir; }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path dir() { return dir_->path(); }
  static testing::TempDir* dir_;

  // Runs `lptn replay` and diffs it against expected/NAME: within 1e-9 (every number), and then
  // byte for byte (the rows as printf printed them when committed: the row formatter's text).
  // A difference rewrites expected/NAME with the fresh rows.
  static void check_replay(const std::string& mode, const std::string& name) {
    const fs::path out = dir() / name;
    const std::string args = "replay --quiet --force " + mode + "--log " + kLog.string() + " --calibration " +
                             kCalibration.string() + " --out " + out.string();
    const Outcome r = run(args, dir());
    ASSERT_EQ(r.code, 0) << "lptn " << args << "\n" << r.err;
    const fs::path expected = kHere / "expected" / name;
    const std::string fresh = slurp(out);
    if (!fs::exists(expected)) {
      write_file(expected, decimated(fresh));
      FAIL() << expected << " was missing; " << kRegenerate;
    }
    const Diff d = diff_replay_csv(fresh, slurp(expected));
    if (d.count > 0) write_file(expected, decimated(fresh));
    EXPECT_EQ(d.count, 0u) << "lptn " << args << "\n" << d.report(expected.string());
    if (d.count == 0) {
      const bool same_bytes = decimated(fresh) == slurp(expected);
      if (!same_bytes) write_file(expected, decimated(fresh));
      EXPECT_TRUE(same_bytes) << name << ": every number within 1e-9 but not the committed bytes (the row's text "
                              << "changed: a format, a column's digits); " << kRegenerate;
    }
  }
};
testing::TempDir* ChangeIndication::dir_ = nullptr;

TEST_F(ChangeIndication, ClosedLoopReplayIsTheCommittedOne) {
  check_replay("", "replay_closed_loop.csv");
}

TEST_F(ChangeIndication, OpenLoopReplayIsTheCommittedOne) {
  check_replay("--open-loop ", "replay_open_loop.csv");
}

TEST_F(ChangeIndication, LmCalibrationIsTheCommittedOne) {
  const fs::path out = dir() / "calibration_lm.json";
  const std::string args = "calibrate --quiet --force --method lm --seed 1 --data " + kFleet.string() + " --motor " +
                           (kFleet / "motor.toml").string() + " --out " + out.string();
  const Outcome r = run(args, dir());
  ASSERT_EQ(r.code, 0) << "lptn " << args << "\n" << r.err;
  const fs::path expected = kHere / "expected/calibration_lm.json";
  const nlohmann::ordered_json fresh = deterministic_part(nlohmann::ordered_json::parse(slurp(out)));
  const std::string fresh_text = fresh.dump(1) + "\n";
  if (!fs::exists(expected)) {
    write_file(expected, fresh_text);
    FAIL() << expected << " was missing; " << kRegenerate;
  }
  Diff d;
  diff_json(json::parse(fresh_text), json::parse(slurp(expected)), "", d);
  if (d.count > 0) write_file(expected, fresh_text);
  EXPECT_EQ(d.count, 0u) << "lptn " << args << "\n" << d.report(expected.string());
}

// ---- the committed files are worth comparing against: they exercise what they should

TEST(ChangeIndicationData, TheCommittedOutputsExerciseTheCorrectionAndTheFit) {
  // Closed loop must differ from open loop, or the closed-loop file would not watch the gate,
  // the fusion or the process noise at all.
  const std::string open = slurp(kHere / "expected/replay_open_loop.csv");
  const std::string closed = slurp(kHere / "expected/replay_closed_loop.csv");
  ASSERT_FALSE(open.empty());
  EXPECT_NE(open, closed);
  std::istringstream in(closed);
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> names = split_csv(line);
  const auto col = [&](const char* n) { return std::find(names.begin(), names.end(), n) - names.begin(); };
  const auto sensor = col("stator_sensor"), ratio = col("test_ratio");
  ASSERT_LT(static_cast<std::size_t>(sensor), names.size());
  std::size_t rows = 0, fused = 0;
  for (; std::getline(in, line); ++rows) {
    const std::vector<std::string> c = split_csv(line);
    double r = 0;
    // Sensor state 0 is "fused" (the status frame's order); a nonzero test ratio: a reading was tested.
    if (c.at(sensor) == "0" && as_number(c.at(ratio), r) && r > 0) ++fused;
  }
  EXPECT_GE(rows, 250u) << "at least 5 minutes at one row a second";
  EXPECT_GT(fused, rows / 2) << "the stator reading is fused most of the time";

  // LM moved the parameters from the motor file's initial guesses, with standard errors.
  const json cal = json::parse(slurp(kHere / "expected/calibration_lm.json"));
  std::size_t fitted = 0;
  for (const json& p : cal.at("parameters"))
    if (p.at("calibrated").get<bool>() && p.at("std_error").is_number()) ++fitted;
  EXPECT_GE(fitted, 6u) << "the paper's six conductances at least";
  EXPECT_FALSE(cal.at("metrics").at("test").at("cycles").empty()) << "a held-out cycle";
}

}  // namespace
}  // namespace lptn::cli
