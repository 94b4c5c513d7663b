// The `lptn inspect` report (text and JSON) and the nameplate plausibility check.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test_util.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/data/inspection.hpp"

namespace lptn::data {
namespace {

using namespace test;

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// 10 Hz fast channels, winding sensor at 1 Hz, ambient at 0.2 Hz, a 20 s hole in the winding
// sensor and a 0.5 s one in speed; 300 s.
Dataset mixed_rate_dataset(const TempDir& dir) {
  std::vector<Col> cols = standard_cols();
  replace_col(cols, {"stator_winding_c", [](std::size_t i, double t) {
                       return i % 10 == 0 && !(i > 1000 && i < 1200) ? std::optional(stator_of(t)) : std::nullopt;
                     }});
  replace_col(cols, {"ambient_c", [](std::size_t i, double t) {
                       return i % 50 == 0 ? std::optional(ambient_of(t)) : std::nullopt;
                     }});
  replace_col(cols, {"speed_rpm", [](std::size_t i, double t) {
                       return i > 500 && i < 505 ? std::nullopt : std::optional(speed_of(t));
                     }});
  return load_fleet_dump({dir.write("depot_a.csv", build_csv(regular_times(3001, 0.1), cols))});
}

TEST(Report, TextShowsRatesCoverageGapsFindingsAndSummary) {
  TempDir dir;
  const Dataset d = mixed_rate_dataset(dir);
  const std::string text = format_report(d);
  SCOPED_TRACE(text);
  EXPECT_TRUE(contains(text, "depot_a  (" + (dir.path() / "depot_a.csv").string() + ")"));
  EXPECT_TRUE(contains(text, "duration 300 s (0.08 h), 3001 rows"));
  EXPECT_TRUE(contains(text, "  speed_rpm              10.000       2997    100.0%     1\n"));
  EXPECT_TRUE(contains(text, "  ambient_c               0.200         61    100.0%     0\n"));
  // 199 of 3001 grid points masked.
  EXPECT_TRUE(contains(text, "  stator_winding_c        1.000        282     93.4%     1\n"));
  EXPECT_TRUE(contains(text, "  rotor_c                absent\n"));
  EXPECT_TRUE(contains(text, "    stator_winding_c   at 100 s for 20 s (lines 1002..1202): masked\n"));
  EXPECT_TRUE(contains(text, "    speed_rpm          at 50 s for 0.5 s (lines 502..507): bridged\n"));
  EXPECT_TRUE(contains(text, "warning: " + (dir.path() / "depot_a.csv").string() + ": column 'stator_winding_c'"));
  EXPECT_TRUE(contains(text, "info: "));
  EXPECT_TRUE(contains(text, "  cycles: depot_a (t=0..300 s)\n"));
  EXPECT_TRUE(text.ends_with("\n1 cycles, 0.08 h of data, 1 warnings\n"));
}

TEST(Report, JsonCarriesTheSameContent) {
  TempDir dir;
  const Dataset d = mixed_rate_dataset(dir);
  const nlohmann::json j = report_json(d);
  ASSERT_EQ(j.at("cycles").size(), 1u);
  const auto& c = j.at("cycles").at(0);
  EXPECT_EQ(c.at("name"), "depot_a");
  EXPECT_EQ(c.at("file"), (dir.path() / "depot_a.csv").string());
  EXPECT_DOUBLE_EQ(c.at("duration_s").get<double>(), 300.0);
  EXPECT_EQ(c.at("rows"), 3001);
  const auto& ch = c.at("channels");
  EXPECT_EQ(ch.size(), static_cast<std::size_t>(kNumChannels));
  EXPECT_NEAR(ch.at("speed_rpm").at("native_rate_hz").get<double>(), 10.0, 1e-6);
  EXPECT_NEAR(ch.at("stator_winding_c").at("native_rate_hz").get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(ch.at("ambient_c").at("native_rate_hz").get<double>(), 0.2, 1e-9);
  EXPECT_EQ(ch.at("ambient_c").at("samples"), 61);
  EXPECT_DOUBLE_EQ(ch.at("speed_rpm").at("coverage").get<double>(), 1.0);
  EXPECT_NEAR(ch.at("stator_winding_c").at("coverage").get<double>(), (3001.0 - 199.0) / 3001.0, 1e-12);
  EXPECT_EQ(ch.at("rotor_c").at("present"), false);
  EXPECT_EQ(ch.at("voltage_v").at("present"), true);
  const auto& gaps = ch.at("stator_winding_c").at("gaps");
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_DOUBLE_EQ(gaps.at(0).at("start_s").get<double>(), 100.0);
  EXPECT_DOUBLE_EQ(gaps.at(0).at("end_s").get<double>(), 120.0);
  EXPECT_EQ(gaps.at(0).at("action"), "masked");
  EXPECT_EQ(ch.at("speed_rpm").at("gaps").at(0).at("action"), "bridged");
  bool warned = false;
  for (const auto& f : c.at("findings")) {
    warned = warned || (f.at("severity") == "warning" &&
                        contains(f.at("message").get<std::string>(), "stator_winding_c"));
  }
  EXPECT_TRUE(warned);
  EXPECT_EQ(j.at("warnings"), 1);
  EXPECT_EQ(j.at("cycle_count"), 1);
  ASSERT_EQ(c.at("segments").size(), 1u);
  EXPECT_EQ(c.at("segments").at(0).at("steps"), 3001);
  // Survives a round trip through text (no NaN/inf sneaking in).
  EXPECT_EQ(nlohmann::json::parse(j.dump()), j);
}

TEST(Report, SplitCycleListsItsSegments) {
  TempDir dir;
  std::vector<Col> cols = standard_cols();
  replace_col(cols, {"frequency_hz", [](std::size_t i, double t) {
                       return i > 1000 && i < 1100 ? std::nullopt : std::optional(frequency_of(t));
                     }});
  const Dataset d = load_fleet_dump({dir.write("s.csv", build_csv(regular_times(3001, 0.1), cols))});
  const std::string text = format_report(d);
  EXPECT_TRUE(contains(text, "  cycles: s (t=0..100 s) s-2 (t=110..300 s)\n")) << text;
  EXPECT_TRUE(contains(text, "frequency_hz       at 100 s for 10 s (lines 1002..1102): split")) << text;
  EXPECT_TRUE(text.ends_with("\n2 cycles, 0.08 h of data, 1 warnings\n")) << text;
  const nlohmann::json j = report_json(d);
  EXPECT_EQ(j.at("cycle_count"), 2);
  EXPECT_EQ(j.at("cycles").at(0).at("segments").at(1).at("name"), "s-2");
}

TEST(Nameplate, ConsistentDataRaisesNothing) {
  const Dataset d = parse_cycle_csv(build_csv(regular_times(600, 0.1), standard_cols()), "ok.csv");
  EXPECT_TRUE(check_against_nameplate(d, {2, 50.0, 200.0, 1500.0}).empty());
}

TEST(Nameplate, OvercurrentOvervoltageAndWrongPolePairsAreReported) {
  std::vector<Col> cols = standard_cols();
  // 10 of 600 steps above 4x a 30 A rating; voltage 1000 V against a 700 V rating.
  replace_col(cols, {"current_a", [](std::size_t i, double) { return std::optional(i < 10 ? 130.0 : 50.0); }});
  const Dataset d = parse_cycle_csv(build_csv(regular_times(600, 0.1), cols), "hot.csv");
  const auto findings = check_against_nameplate(d, {2, 50.0, 30.0, 700.0});
  ASSERT_EQ(findings.size(), 2u);
  EXPECT_TRUE(contains(findings[0].message, "cycle hot (hot.csv): current_a above 4x")) << findings[0].message;
  EXPECT_TRUE(contains(findings[0].message, "at 10 of 600 steps")) << findings[0].message;
  EXPECT_TRUE(contains(findings[1].message, "voltage_v above 1.3x")) << findings[1].message;
  EXPECT_EQ(findings[1].severity, Finding::Severity::warning);

  // The data was made with 2 pole pairs; 3 puts the frequency ~17 Hz off everywhere.
  const auto wrong = check_against_nameplate(d, {3, 50.0, 1000.0, 2000.0});
  ASSERT_EQ(wrong.size(), 1u);
  EXPECT_TRUE(contains(wrong[0].message, "frequency_hz")) << wrong[0].message;
  EXPECT_TRUE(contains(wrong[0].message, "600 of 600 steps (100.0%)")) << wrong[0].message;

  EXPECT_THROW((void)check_against_nameplate(d, {0, 50.0, 1.0, 1.0}), std::invalid_argument);
}

TEST(Nameplate, ReverseRunningAndSlipAreNotMismatches) {
  std::vector<Col> cols = standard_cols();
  // Reverse, frequency logged unsigned and 3 Hz of slip above synchronous.
  replace_col(cols, {"speed_rpm", [](std::size_t, double t) { return std::optional(-speed_of(t)); }});
  replace_col(cols, {"frequency_hz", [](std::size_t, double t) { return std::optional(frequency_of(t) + 3.0); }});
  const Dataset d = parse_cycle_csv(build_csv(regular_times(600, 0.1), cols), "rev.csv");
  EXPECT_TRUE(check_against_nameplate(d, {2, 50.0, 200.0, 1500.0}).empty());
}

TEST(Nameplate, FewMismatchesAreTolerated) {
  std::vector<Col> cols = standard_cols();
  // 5 of 600 rows (< 1%) with a garbage frequency.
  replace_col(cols, {"frequency_hz", [](std::size_t i, double t) {
                       return std::optional(i % 120 == 7 ? 400.0 : frequency_of(t));
                     }});
  const Dataset d = parse_cycle_csv(build_csv(regular_times(600, 0.1), cols), "few.csv");
  EXPECT_TRUE(check_against_nameplate(d, {2, 50.0, 200.0, 1500.0}).empty());
}

}  // namespace
}  // namespace lptn::data
