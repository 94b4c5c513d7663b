// Loading and resampling: layout independence, mixed rates, gaps, splits, directories.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "test_util.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn::data {
namespace {

using namespace test;

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

std::size_t count_warnings_with(const CycleReport& r, const std::string& part) {
  return static_cast<std::size_t>(std::count_if(r.findings.begin(), r.findings.end(), [&](const Finding& f) {
    return f.severity == Finding::Severity::warning && contains(f.message, part);
  }));
}

// Bitwise sample equality, NaN == NaN.
void expect_same_cycles(const Dataset& a, const Dataset& b) {
  ASSERT_EQ(a.cycles.size(), b.cycles.size());
  for (std::size_t n = 0; n < a.cycles.size(); ++n) {
    const Cycle& x = a.cycles[n];
    const Cycle& y = b.cycles[n];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.t0_s, y.t0_s);
    EXPECT_EQ(x.dt_s, y.dt_s);
    ASSERT_EQ(x.steps, y.steps);
    for (Channel c : kAllChannels) {
      const auto& u = x.samples[index_of(c)];
      const auto& v = y.samples[index_of(c)];
      ASSERT_EQ(u.size(), v.size()) << channel_name(c);
      for (std::size_t k = 0; k < u.size(); ++k) {
        if (std::isnan(u[k]) || std::isnan(v[k])) {
          ASSERT_TRUE(std::isnan(u[k]) && std::isnan(v[k])) << channel_name(c) << " k=" << k;
        } else {
          ASSERT_EQ(u[k], v[k]) << channel_name(c) << " k=" << k;
        }
      }
    }
  }
  ASSERT_EQ(a.reports.size(), b.reports.size());
  for (std::size_t n = 0; n < a.reports.size(); ++n) {
    for (Channel c : kAllChannels) {
      const ChannelReport& p = a.reports[n].channels[index_of(c)];
      const ChannelReport& q = b.reports[n].channels[index_of(c)];
      EXPECT_EQ(p.present, q.present);
      EXPECT_EQ(p.samples, q.samples);
      EXPECT_EQ(p.native_rate_hz, q.native_rate_hz);
      EXPECT_EQ(p.coverage, q.coverage);
      EXPECT_EQ(p.gaps.size(), q.gaps.size());
    }
  }
}

TEST(Loader, LinearSignalsOnARegularGrid) {
  TempDir dir;
  const auto file = dir.write("plain.csv", build_csv(regular_times(1201, 0.1), standard_cols()));
  const Dataset d = load_fleet_dump({file});
  ASSERT_EQ(d.cycles.size(), 1u);
  const Cycle& c = d.cycles[0];
  EXPECT_EQ(c.name, "plain");
  EXPECT_EQ(c.file, file);
  EXPECT_EQ(c.steps, 1201u);
  EXPECT_DOUBLE_EQ(c.t0_s, 0.0);
  for (std::size_t k = 0; k < c.steps; k += 37) {
    const double t = c.time_s(k);
    EXPECT_NEAR(c.at(Channel::speed_rpm, k), speed_of(t), 1e-3);
    EXPECT_NEAR(c.at(Channel::stator_winding_c, k), stator_of(t), 1e-4);
  }
  EXPECT_EQ(d.warning_count(), 0u);
  EXPECT_EQ(d.reports[0].rows, 1201u);
  EXPECT_DOUBLE_EQ(d.reports[0].duration_s, 120.0);
}

TEST(Loader, CrlfLoadsIdenticallyToLf) {
  TempDir dir;
  std::vector<Col> cols = standard_cols();
  replace_col(cols, {"stator_winding_c", [](std::size_t i, double t) {
                       return i % 10 == 0 ? std::optional<double>(stator_of(t)) : std::nullopt;
                     }});
  const auto times = regular_times(900, 0.1);
  const Dataset lf = load_fleet_dump({dir.write("lf/cycle.csv", build_csv(times, cols, "\n"))});
  const Dataset crlf = load_fleet_dump({dir.write("crlf/cycle.csv", build_csv(times, cols, "\r\n"))});
  expect_same_cycles(lf, crlf);
  EXPECT_TRUE(lf.cycles[0].has(Channel::stator_winding_c));
}

TEST(Loader, ColumnOrderDoesNotMatter) {
  TempDir dir;
  const auto times = regular_times(700, 0.1);
  std::vector<Col> cols = standard_cols();
  const Dataset ordered = load_fleet_dump({dir.write("a/cycle.csv", build_csv(times, cols))});
  std::reverse(cols.begin(), cols.end());
  std::rotate(cols.begin(), cols.begin() + 3, cols.end());
  ASSERT_NE(cols.front().name, "time_s");
  const Dataset shuffled = load_fleet_dump({dir.write("b/cycle.csv", build_csv(times, cols))});
  expect_same_cycles(ordered, shuffled);
}

TEST(Loader, UnknownColumnWarnsOnceAndIsIgnored) {
  TempDir dir;
  std::vector<Col> cols = standard_cols();
  cols.insert(cols.begin() + 2, Col{"gps_lat", [](std::size_t, double) { return std::optional<double>(48.1); }});
  const auto file = dir.write("extra.csv", build_csv(regular_times(100, 0.1), cols));
  const Dataset d = load_fleet_dump({file});
  ASSERT_EQ(d.cycles.size(), 1u);
  EXPECT_EQ(d.warning_count(), 1u);
  const auto& f = d.reports[0].findings;
  const auto it = std::find_if(f.begin(), f.end(), [](const Finding& x) { return x.severity == Finding::Severity::warning; });
  ASSERT_NE(it, f.end());
  EXPECT_TRUE(contains(it->message, "gps_lat")) << it->message;
  EXPECT_TRUE(contains(it->message, file.string())) << it->message;
}

TEST(Loader, DuplicateTimestampsAreAveraged) {
  const std::string text =
      "time_s,speed_rpm,current_a,frequency_hz,airflow_m3s,ambient_c,stator_winding_c\n"
      "0,1000,100,33,1.5,20,40\n"
      "0.5,1000,100,33,1.5,20,40\n"
      "1.0,1000,100,33,1.5,20,40\n"
      "1.0,1100,,35,1.5,20,\n"
      "1.0,1300,,,1.5,20,\n"
      "1.5,1000,100,33,1.5,20,40\n";
  const Dataset d = parse_cycle_csv(text, "dup.csv");
  ASSERT_EQ(d.cycles.size(), 1u);
  const Cycle& c = d.cycles[0];
  ASSERT_EQ(c.steps, 16u);
  EXPECT_FLOAT_EQ(c.at(Channel::speed_rpm, 10), 1133.3334f);  // (1000+1100+1300)/3
  EXPECT_FLOAT_EQ(c.at(Channel::frequency_hz, 10), 34.0f);
  EXPECT_FLOAT_EQ(c.at(Channel::current_a, 10), 100.0f);
  // Between 0.5 s (1000) and the merged 1.0 s sample.
  EXPECT_NEAR(c.at(Channel::speed_rpm, 8), 1000.0 + 0.6 * (3400.0 / 3.0 - 1000.0), 1e-3);
  EXPECT_EQ(d.reports[0].channels[index_of(Channel::speed_rpm)].samples, 6u);
}

// A logger as it really writes: jittered time stamps, fast channels at 10 Hz, the winding sensor
// at 1 Hz, ambient at 0.2 Hz (empty cells in between), and short dropouts that must be bridged.
TEST(Loader, JitteredMixedRatesResampleToTheAnalyticSignal) {
  constexpr std::size_t kRows = 3001;
  std::vector<double> times(kRows);
  for (std::size_t i = 0; i < kRows; ++i) {
    // Deterministic jitter within +-0.03 s; first and last rows exact so coverage is complete.
    const double jitter = (i == 0 || i + 1 == kRows) ? 0.0 : 0.03 * std::sin(static_cast<double>(i) * 1.7);
    times[i] = 0.1 * static_cast<double>(i) + jitter;
  }
  const auto fast_dropout = [](std::size_t i) { return i >= 1200 && i < 1208; };  // ~0.9 s
  const auto stator_dropout = [](std::size_t i) { return i >= 2010 && i < 2040; };  // one 4 s interval
  const auto current = [](double t) { return 300.0 + 100.0 * std::sin(2.0 * std::numbers::pi * t / 60.0); };

  std::vector<Col> cols = {
      time_col(),
      {"speed_rpm", [&](std::size_t i, double t) { return fast_dropout(i) ? std::nullopt : std::optional(speed_of(t)); }},
      {"current_a", [&](std::size_t i, double t) { return fast_dropout(i) ? std::nullopt : std::optional(current(t)); }},
      {"frequency_hz", [](std::size_t, double t) { return std::optional(frequency_of(t)); }},
      {"airflow_m3s", [](std::size_t, double t) { return std::optional(airflow_of(t)); }},
      {"ambient_c", [](std::size_t i, double t) { return i % 50 == 0 ? std::optional(ambient_of(t)) : std::nullopt; }},
      {"stator_winding_c",
       [&](std::size_t i, double t) {
         return i % 10 == 0 && !stator_dropout(i) ? std::optional(stator_of(t)) : std::nullopt;
       }},
  };
  TempDir dir;
  const auto file = dir.write("jitter.csv", build_csv(times, cols));
  const Dataset d = load_fleet_dump({file});
  ASSERT_EQ(d.cycles.size(), 1u);
  const Cycle& c = d.cycles[0];
  EXPECT_EQ(c.steps, 3001u);
  EXPECT_FALSE(c.has(Channel::rotor_c));
  EXPECT_FALSE(c.has(Channel::torque_nm));

  const double gap_begin = times[1199], gap_end = times[1208];
  for (std::size_t k = 0; k < c.steps; ++k) {
    const double t = c.time_s(k);
    ASSERT_NEAR(c.at(Channel::speed_rpm, k), speed_of(t), 2e-3) << "t=" << t;
    ASSERT_NEAR(c.at(Channel::frequency_hz, k), frequency_of(t), 1e-4) << "t=" << t;
    ASSERT_NEAR(c.at(Channel::airflow_m3s, k), airflow_of(t), 1e-6) << "t=" << t;
    ASSERT_NEAR(c.at(Channel::ambient_c, k), ambient_of(t), 1e-5) << "t=" << t;
    ASSERT_NEAR(c.at(Channel::stator_winding_c, k), stator_of(t), 1e-4) << "t=" << t;
    // Linear interpolation of a sine: error <= A w^2 h^2 / 8 for sample spacing h.
    const double h = (t > gap_begin && t < gap_end) ? gap_end - gap_begin : 0.16;
    const double w = 2.0 * std::numbers::pi / 60.0;
    ASSERT_NEAR(c.at(Channel::current_a, k), current(t), 100.0 * w * w * h * h / 8.0 + 1e-4) << "t=" << t;
  }

  const CycleReport& r = d.reports[0];
  const auto& speed = r.channels[index_of(Channel::speed_rpm)];
  const auto& stator = r.channels[index_of(Channel::stator_winding_c)];
  const auto& ambient = r.channels[index_of(Channel::ambient_c)];
  EXPECT_NEAR(speed.native_rate_hz, 10.0, 0.3);
  EXPECT_NEAR(stator.native_rate_hz, 1.0, 0.02);
  EXPECT_NEAR(ambient.native_rate_hz, 0.2, 0.003);
  EXPECT_EQ(speed.samples, kRows - 8);
  EXPECT_EQ(stator.samples, 301u - 3u);
  EXPECT_EQ(ambient.samples, 61u);
  EXPECT_DOUBLE_EQ(speed.coverage, 1.0);
  EXPECT_DOUBLE_EQ(stator.coverage, 1.0);
  EXPECT_DOUBLE_EQ(ambient.coverage, 1.0);
  EXPECT_FALSE(r.channels[index_of(Channel::rotor_c)].present);

  ASSERT_EQ(speed.gaps.size(), 1u);
  EXPECT_EQ(speed.gaps[0].action, Gap::Action::bridged);
  EXPECT_DOUBLE_EQ(speed.gaps[0].start_s, gap_begin);
  EXPECT_DOUBLE_EQ(speed.gaps[0].end_s, gap_end);
  EXPECT_EQ(speed.gaps[0].line_before, 1201u);  // row 1199 is on line 1201
  EXPECT_EQ(speed.gaps[0].line_after, 1210u);
  ASSERT_EQ(stator.gaps.size(), 1u);
  EXPECT_EQ(stator.gaps[0].action, Gap::Action::bridged);
  EXPECT_EQ(stator.gaps[0].line_before, 2002u);
  EXPECT_EQ(stator.gaps[0].line_after, 2042u);
  EXPECT_TRUE(r.channels[index_of(Channel::ambient_c)].gaps.empty());
  EXPECT_EQ(d.warning_count(), 0u);
}

std::vector<Col> with_gap(std::string channel, double from, double to) {
  std::vector<Col> cols = standard_cols();
  for (Col& c : cols) {
    if (c.name != channel) continue;
    auto f = c.value;
    c.value = [f, from, to](std::size_t i, double t) {
      return (t > from + 1e-9 && t < to - 1e-9) ? std::nullopt : f(i, t);
    };
  }
  return cols;
}

TEST(Loader, LongGapInWindingSensorIsMasked) {
  // Winding sensor at 1 Hz with nothing between t=100 and t=130.
  std::vector<Col> cols = standard_cols();
  replace_col(cols, {"stator_winding_c", [](std::size_t i, double t) {
                       const bool in_gap = i > 1000 && i < 1300;
                       return i % 10 == 0 && !in_gap ? std::optional(stator_of(t)) : std::nullopt;
                     }});
  TempDir dir;
  const auto file = dir.write("masked.csv", build_csv(regular_times(2001, 0.1), cols));
  const Dataset d = load_fleet_dump({file});
  ASSERT_EQ(d.cycles.size(), 1u);
  const Cycle& c = d.cycles[0];
  ASSERT_EQ(c.steps, 2001u);
  for (std::size_t k = 0; k < c.steps; ++k) {
    const bool inside = k > 1000 && k < 1300;
    EXPECT_EQ(std::isnan(c.at(Channel::stator_winding_c, k)), inside) << "k=" << k;
    EXPECT_FALSE(std::isnan(c.at(Channel::speed_rpm, k))) << "k=" << k;
  }
  EXPECT_NEAR(c.at(Channel::stator_winding_c, 1000), stator_of(100.0), 1e-4);
  EXPECT_NEAR(c.at(Channel::stator_winding_c, 1300), stator_of(130.0), 1e-4);

  const CycleReport& r = d.reports[0];
  const auto& stator = r.channels[index_of(Channel::stator_winding_c)];
  ASSERT_EQ(stator.gaps.size(), 1u);
  EXPECT_EQ(stator.gaps[0].action, Gap::Action::masked);
  EXPECT_DOUBLE_EQ(stator.gaps[0].start_s, 100.0);
  EXPECT_DOUBLE_EQ(stator.gaps[0].end_s, 130.0);
  EXPECT_NEAR(stator.coverage, (2001.0 - 299.0) / 2001.0, 1e-12);
  EXPECT_EQ(d.warning_count(), 1u);
  EXPECT_EQ(count_warnings_with(r, "column 'stator_winding_c'"), 1u);
  EXPECT_EQ(count_warnings_with(r, "t=100 s (line 1002) to t=130 s (line 1302)"), 1u);
  EXPECT_EQ(count_warnings_with(r, file.string()), 1u);
  EXPECT_EQ(count_warnings_with(r, "masked"), 1u);
}

TEST(Loader, LongGapInSpeedSplitsTheCycle) {
  TempDir dir;
  const auto file = dir.write("run7.csv", build_csv(regular_times(3001, 0.1), with_gap("speed_rpm", 100.0, 110.0)));
  const Dataset d = load_fleet_dump({file});
  ASSERT_EQ(d.cycles.size(), 2u);
  EXPECT_EQ(d.cycles[0].name, "run7");
  EXPECT_EQ(d.cycles[1].name, "run7-2");  // shell-safe: no quoting needed on a command line
  EXPECT_DOUBLE_EQ(d.cycles[0].t0_s, 0.0);
  EXPECT_EQ(d.cycles[0].steps, 1001u);  // 0 .. 100 s
  EXPECT_NEAR(d.cycles[1].t0_s, 110.0, 1e-9);
  EXPECT_EQ(d.cycles[1].steps, 1901u);  // 110 .. 300 s
  for (const Cycle& c : d.cycles) {
    for (std::size_t k = 0; k < c.steps; ++k) {
      ASSERT_NEAR(c.at(Channel::speed_rpm, k), speed_of(c.time_s(k)), 1e-3);
      ASSERT_NEAR(c.at(Channel::current_a, k), current_of(c.time_s(k)), 1e-4);
    }
  }
  ASSERT_EQ(d.reports.size(), 1u);
  const auto& gaps = d.reports[0].channels[index_of(Channel::speed_rpm)].gaps;
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_EQ(gaps[0].action, Gap::Action::split);
  EXPECT_EQ(gaps[0].line_before, 1002u);
  EXPECT_EQ(gaps[0].line_after, 1102u);
  EXPECT_EQ(count_warnings_with(d.reports[0], "column 'speed_rpm'"), 1u);
  EXPECT_EQ(count_warnings_with(d.reports[0], "(line 1002)"), 1u);
  EXPECT_EQ(d.warning_count(), 1u);
}

TEST(Loader, ShortSegmentAfterSplitIsDropped) {
  TempDir dir;
  const auto file = dir.write("short.csv", build_csv(regular_times(3001, 0.1), with_gap("airflow_m3s", 30.0, 45.0)));
  const Dataset d = load_fleet_dump({file});
  ASSERT_EQ(d.cycles.size(), 1u);
  EXPECT_EQ(d.cycles[0].name, "short");  // the first kept segment carries the plain name
  EXPECT_NEAR(d.cycles[0].t0_s, 45.0, 1e-9);
  EXPECT_EQ(d.cycles[0].steps, 2551u);
  EXPECT_EQ(count_warnings_with(d.reports[0], "dropped"), 1u);
  EXPECT_EQ(d.warning_count(), 2u);  // the split and the drop
}

TEST(Loader, RaisingTheGapLimitBridgesInstead) {
  LoadOptions o;
  o.max_gap_s[index_of(Channel::speed_rpm)] = 20.0;
  const Dataset d =
      parse_cycle_csv(build_csv(regular_times(3001, 0.1), with_gap("speed_rpm", 100.0, 110.0)), "x.csv", o);
  ASSERT_EQ(d.cycles.size(), 1u);
  EXPECT_EQ(d.reports[0].channels[0].gaps.at(0).action, Gap::Action::bridged);
  EXPECT_NEAR(d.cycles[0].at(Channel::speed_rpm, 1050), speed_of(105.0), 1e-3);
  EXPECT_EQ(d.warning_count(), 0u);
}

TEST(Loader, CoarserGrid) {
  LoadOptions o;
  o.dt_s = 1.0;
  const Dataset d = parse_cycle_csv(build_csv(regular_times(1001, 0.1), standard_cols()), "coarse.csv", o);
  ASSERT_EQ(d.cycles.size(), 1u);
  EXPECT_EQ(d.cycles[0].steps, 101u);
  EXPECT_NEAR(d.cycles[0].at(Channel::speed_rpm, 37), speed_of(37.0), 1e-3);
}

TEST(Loader, LateStartingDriverTrimsTheCycle) {
  std::vector<Col> cols = standard_cols();
  replace_col(cols, {"ambient_c", [](std::size_t, double t) {
                       return t >= 5.0 - 1e-9 ? std::optional(ambient_of(t)) : std::nullopt;
                     }});
  const Dataset d = parse_cycle_csv(build_csv(regular_times(1001, 0.1), cols), "late.csv");
  ASSERT_EQ(d.cycles.size(), 1u);
  EXPECT_NEAR(d.cycles[0].t0_s, 5.0, 1e-9);
  EXPECT_EQ(d.cycles[0].steps, 951u);
  EXPECT_EQ(d.warning_count(), 0u);
  const auto& f = d.reports[0].findings;
  EXPECT_TRUE(std::any_of(f.begin(), f.end(), [](const Finding& x) {
    return x.severity == Finding::Severity::info && contains(x.message, "ambient_c");
  }));
}

TEST(Loader, RotorAbsentIsFineRotorPresentIsUsed) {
  TempDir dir;
  const auto times = regular_times(600, 0.1);
  const Dataset without = load_fleet_dump({dir.write("no_rotor.csv", build_csv(times, standard_cols()))});
  ASSERT_EQ(without.cycles.size(), 1u);
  EXPECT_FALSE(without.cycles[0].has(Channel::rotor_c));
  EXPECT_TRUE(without.cycles[0].samples[index_of(Channel::rotor_c)].empty());
  EXPECT_TRUE(std::isnan(without.cycles[0].at(Channel::rotor_c, 10)));
  EXPECT_THROW((void)without.cycles[0].at(Channel::rotor_c, 600), std::out_of_range);
  EXPECT_EQ(without.warning_count(), 0u);
  const auto& f = without.reports[0].findings;
  EXPECT_TRUE(std::any_of(f.begin(), f.end(), [](const Finding& x) {
    return x.severity == Finding::Severity::info && contains(x.message, "rotor_c");
  }));

  std::vector<Col> cols = standard_cols();
  cols.push_back(signal_col("rotor_c", rotor_of));
  const Dataset with = load_fleet_dump({dir.write("rotor.csv", build_csv(times, cols))});
  ASSERT_TRUE(with.cycles[0].has(Channel::rotor_c));
  EXPECT_NEAR(with.cycles[0].at(Channel::rotor_c, 100), rotor_of(10.0), 1e-4);
}

TEST(Loader, DirectoryLoadsItsCsvFilesSortedByName) {
  TempDir dir;
  const std::string csv = build_csv(regular_times(100, 0.1), standard_cols());
  dir.write("dump/cycle_b.csv", csv);
  dir.write("dump/cycle_a.csv", csv);
  dir.write("dump/cycle_c.CSV", csv);
  dir.write("dump/readme.txt", "not data\n");
  dir.write("dump/nested/cycle_0.csv", csv);
  const Dataset d = load_fleet_dump({dir.path() / "dump"});
  ASSERT_EQ(d.cycles.size(), 3u);
  EXPECT_EQ(d.cycles[0].name, "cycle_a");
  EXPECT_EQ(d.cycles[1].name, "cycle_b");
  EXPECT_EQ(d.cycles[2].name, "cycle_c");
  ASSERT_EQ(d.reports.size(), 3u);
  EXPECT_EQ(d.reports[0].file.filename(), "cycle_a.csv");

  // Files and directories mixed, in the order given; the same file twice is loaded once.
  const Dataset mixed = load_fleet_dump({dir.path() / "dump" / "nested" / "cycle_0.csv", dir.path() / "dump",
                                         dir.path() / "dump" / "cycle_a.csv"});
  ASSERT_EQ(mixed.cycles.size(), 4u);
  EXPECT_EQ(mixed.cycles[0].name, "cycle_0");
  EXPECT_EQ(mixed.cycles[1].name, "cycle_a");
}

TEST(Loader, InMemoryAndFileAgree) {
  TempDir dir;
  const std::string csv = build_csv(regular_times(500, 0.1), with_gap("stator_winding_c", 10.0, 30.0));
  expect_same_cycles(parse_cycle_csv(csv, dir.path() / "m.csv"), load_cycle_file(dir.write("m.csv", csv)));
}

}  // namespace
}  // namespace lptn::data
