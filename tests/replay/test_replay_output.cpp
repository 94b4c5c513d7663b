// The replay's output, written fast, is the bytes it was: the CSV's numbers without printf are
// printf's (every kind of double, every field of a row), a fresh replay of the change-indication log
// is the committed rows byte for byte, and a directory of logs replayed over several threads is,
// log for log, what each replayed alone writes. A bad log of a directory is one line naming it, and
// nothing is written. `lptn convert` of a directory over the cores is its files one at a time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "lptn_testing/run_lptn.hpp"
#include "lptn_testing/temp_dir.hpp"
#include "firmware/linux/csv_number.hpp"
#include "firmware/linux/estimate_csv.hpp"
#include "can/canfile/can_log.hpp"

namespace lptn::replay {
namespace {

namespace fs = std::filesystem;
using testing::run;
using testing::slurp;
using testing::TempDir;

const fs::path kSource = LPTN_SOURCE_DIR;
const fs::path kCalibration = kSource / "firmware/calibration/default_calibration.json";
const fs::path kChangeIndication = kSource / "tests/change_indication";
const fs::path kLog = kChangeIndication / "input/cycle.log";

std::string printf_string(const char* format, double v) {
  char buf[400];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string fixed6(double v) {
  char buf[400];
  return std::string(buf, fw::csv_number::put_fixed6(buf, v));
}

std::string general9(double v) {
  char buf[400];
  return std::string(buf, fw::csv_number::put_general9(buf, v));
}

// Doubles of every kind: random bits (every exponent, subnormals, NaN payloads), decimals of every
// magnitude, floats widened, values on the sixth decimal and ties of it (k/2^n), and the edges.
std::vector<double> all_kinds_of_doubles(std::size_t n) {
  std::vector<double> v = {0.0,
                           -0.0,
                           1.0 / 128,  // 0.0078125: a tie at the sixth decimal, rounded to even
                           -1.0 / 128,
                           3.0 / 128,
                           5e-7,
                           -5e-7,
                           4.9999995e-7,
                           1e-7,
                           -1e-7,
                           9.2e12,
                           9.19999999e12,
                           -9.2e12,
                           1e300,
                           -1e300,
                           123456789.0,
                           1234567890.0,
                           999999999.5,
                           99999.9999995,
                           1e-4,
                           1e-5,
                           0.1,
                           std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN(),
                           -std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::denorm_min(),
                           std::numeric_limits<double>::min(),
                           std::numeric_limits<double>::max(),
                           std::numeric_limits<double>::lowest()};
  std::mt19937_64 g(20261127);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> exponent(-12, 14);
  for (std::size_t i = 0; i < n; ++i) {
    const double d = u(g) * std::pow(10.0, exponent(g));
    std::uint64_t bits = g();
    double r;
    std::memcpy(&r, &bits, sizeof r);
    v.insert(v.end(), {d, static_cast<double>(static_cast<float>(d)), std::round(d * 1e6) / 1e6,
                       std::ldexp(std::round(std::ldexp(d, 20)), -27), r});
  }
  // Ties at the ninth significant digit ("%.9g" rounds them to even): odd / 2^(9 - X) in the
  // decade 10^X is exactly (ninth digit) + 1/2; and the doubles next to each decade's boundary,
  // where nine digits round up into the next decade (and into or out of the exponent form).
  std::size_t ties = 0;
  for (int x = -6; x <= 9; ++x) {
    const double lo = std::pow(10.0, x), hi = std::pow(10.0, x + 1);
    // The odd numerators whose quotient lies in the decade.
    std::uniform_real_distribution<double> in_decade(std::ldexp(lo, 9 - x) / 2, std::ldexp(hi, 9 - x) / 2);
    for (int i = 0; i < 2000; ++i) {
      const double t = std::ldexp(2 * std::floor(in_decade(g)) + 1, -(9 - x));
      if (t >= lo && t < hi) {
        v.insert(v.end(), {t, -t});
        ++ties;
      }
      const double u1 = lo * (1.0 + u(g) * 1e-8);
      v.insert(v.end(), {u1, std::nextafter(lo, 0.0), std::nextafter(lo, 1e300), lo * (1.0 - 5e-10), lo * (1.0 - 4.9e-10),
                         -u1});
    }
  }
  EXPECT_GT(ties, 20000u);  // the ties are there
  return v;
}

TEST(CsvNumber, FixedAndGeneralAreWhatPrintfWrites) {
  std::size_t fixed_wrong = 0, general_wrong = 0;
  for (double v : all_kinds_of_doubles(200000)) {
    if (fixed6(v) != printf_string("%.6f", v) && ++fixed_wrong <= 5)
      ADD_FAILURE() << "%.6f of " << printf_string("%.17g", v) << ": printf " << printf_string("%.6f", v) << ", got "
                    << fixed6(v);
    if (general9(v) != printf_string("%.9g", v) && ++general_wrong <= 5)
      ADD_FAILURE() << "%.9g of " << printf_string("%.17g", v) << ": printf " << printf_string("%.9g", v) << ", got "
                    << general9(v);
  }
  EXPECT_EQ(fixed_wrong, 0u);
  EXPECT_EQ(general_wrong, 0u);
}

// The row as the printf-based writer (before csv_number.hpp) wrote it.
std::string printf_row(const fw::EstimatorOutput<double>& o, fw::TimeUs t0_us) {
  char buf[fw::kMaxEstimateRow];
  std::string s;
  auto put = [&](double v) {
    if (std::isnan(v)) {
      s += ',';
    } else {
      std::snprintf(buf, sizeof buf, ",%.9g", v);
      s += buf;
    }
  };
  const fw::TimeUs t = o.time_us - t0_us;
  std::snprintf(buf, sizeof buf, "%lld.%06lld", static_cast<long long>(t / fw::kUsPerS),
                static_cast<long long>(t % fw::kUsPerS));
  s += buf;
  const auto& in = o.inputs;
  put(in.speed_rpm);
  put(in.has_torque ? in.torque_nm : NAN);
  put(in.current_a);
  put(in.frequency_hz);
  put(in.has_voltage ? in.voltage_v : NAN);
  put(in.airflow_m3s);
  put(in.ambient_c);
  put(o.stator_reading_c);
  put(o.rotor_reading_c);
  for (double v : o.node_c) std::snprintf(buf, sizeof buf, ",%.6f", v), s += buf;
  for (double v : o.node_std_k) std::snprintf(buf, sizeof buf, ",%.6f", v), s += buf;
  std::snprintf(buf, sizeof buf, ",%d,%.6f,%.6f,%u,%u,%.6f,%.6f,%.6f,%u,%u,%u,%u,%d,%d,%d,%u,%.6f,%.6f,%u,%d\n",
                o.limiting_node, o.margin_k, o.margin_conservative_k, static_cast<unsigned>(o.mode),
                static_cast<unsigned>(o.sensor), o.fusion.innovation_k, o.fusion.innovation_std_k, o.fusion.test_ratio,
                static_cast<unsigned>(o.rejected_readings), static_cast<unsigned>(o.stale),
                static_cast<unsigned>(o.implausible), static_cast<unsigned>(o.substituted), o.torque_route ? 1 : 0,
                o.voltage_route ? 1 : 0, o.actor_scheduling ? 1 : 0, static_cast<unsigned>(o.bus_events),
                o.cooling_factor, o.cooling_factor_std, static_cast<unsigned>(o.cooling_state), o.cooling_alarm ? 1 : 0);
  s += buf;
  return s;
}

// Every row twice: alone (format_estimate_row) and by one EstimateRowFormatter for all rows in
// turn, most of whose numbers are those of the row before or differ from them only in sign (+0 and
// -0, NaN of either sign among them) or in the last bit.
TEST(EstimateRow, IsTheRowPrintfWrote) {
  const std::vector<double> values = all_kinds_of_doubles(20000);
  std::mt19937_64 g(7);
  std::uniform_int_distribution<std::size_t> pick(0, values.size() - 1);
  std::uniform_int_distribution<int> small(0, 7);
  std::uniform_int_distribution<long long> time(-5 * fw::kUsPerS, 400000 * fw::kUsPerS);
  std::vector<double> previous, current;  // the rows' numbers, column by column as any() hands them out
  std::size_t column = 0;
  auto any = [&] {
    double v = values[pick(g)];
    if (column < previous.size()) {
      const double old = previous[column];
      switch (small(g)) {
        case 0: case 1: case 2: case 3: v = old; break;
        case 4: v = -old; break;
        case 5: v = std::nextafter(old, INFINITY); break;
        default: break;
      }
    }
    ++column;
    current.push_back(v);
    return v;
  };
  fw::EstimateRowFormatter rows;
  for (int i = 0; i < 20000; ++i) {
    previous.swap(current);
    current.clear();
    column = 0;
    fw::EstimatorOutput<double> o;
    o.time_us = time(g);
    o.inputs.speed_rpm = any();
    o.inputs.has_torque = small(g) > 1;
    o.inputs.torque_nm = any();
    o.inputs.current_a = any();
    o.inputs.frequency_hz = any();
    o.inputs.has_voltage = small(g) > 1;
    o.inputs.voltage_v = any();
    o.inputs.airflow_m3s = any();
    o.inputs.ambient_c = any();
    o.stator_reading_c = any();
    o.rotor_reading_c = any();
    for (double& v : o.node_c) v = any();
    for (double& v : o.node_std_k) v = any();
    o.limiting_node = small(g) - 2;
    o.margin_k = any();
    o.margin_conservative_k = any();
    o.fusion.innovation_k = any();
    o.fusion.innovation_std_k = any();
    o.fusion.test_ratio = any();
    o.rejected_readings = static_cast<std::uint32_t>(g());
    o.stale = static_cast<fw::InputMask>(g());
    o.bus_events = static_cast<std::uint8_t>(g());
    o.cooling_factor = any();
    o.cooling_factor_std = any();
    o.torque_route = small(g) > 3;
    o.cooling_alarm = small(g) > 3;
    const fw::TimeUs t0 = small(g) > 5 ? o.time_us + 1 : 0;  // now and then a time before the log's start
    char buf[fw::kMaxEstimateRow];
    const std::string row(buf, fw::format_estimate_row(buf, o, t0));
    ASSERT_EQ(row, printf_row(o, t0)) << "row " << i;
    const std::string in_turn(buf, rows.format(buf, o, t0));
    ASSERT_EQ(in_turn, row) << "row " << i << ", formatted in turn";
  }
}

// A directory of logs: the change-indication log as candump, as lptn's ASC and BLF, and its first
// half as a second candump log.
class ReplayDirectory : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    const fs::path logs = dir_->path() / "logs";
    fs::create_directories(logs);
    fs::copy_file(kLog, logs / "a_candump.log");
    std::ifstream in(kLog);
    std::ofstream half(logs / "d_half.log");
    std::string line;
    std::vector<std::string> lines;
    while (std::getline(in, line)) lines.push_back(line);
    for (std::size_t i = 0; i < lines.size() / 2; ++i) half << lines[i] << '\n';
    half.close();
    for (const canfile::LogFormat f : {canfile::LogFormat::asc, canfile::LogFormat::blf}) {
      canfile::OpenedLog log = canfile::open_log(kLog, canfile::LogSelection{});
      const auto writer = canfile::make_log_writer(f);
      fw::TimeUs t;
      fw::CanFrame frame;
      const char* why;
      for (frames::FrameSource::Status s; (s = log.frames->next(t, frame, why)) != frames::FrameSource::Status::end;)
        if (s == frames::FrameSource::Status::frame) writer->add(t, frame);
      std::ofstream(logs / (std::string(f == canfile::LogFormat::asc ? "b_asc" : "c_blf") + canfile::format_extension(f)),
                    std::ios::binary)
          << writer->finish();
    }
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path path(const std::string& name) { return dir_->path() / name; }
  static testing::Result replay(const std::string& args) {
    return run("replay --quiet --calibration " + kCalibration.string() + " " + args, dir_->path());
  }
  static TempDir* dir_;
};
TempDir* ReplayDirectory::dir_ = nullptr;

// stdout without the last line (the total, which carries the wall time).
std::string without_total(const std::string& out) {
  const std::size_t end = out.rfind('\n', out.size() >= 2 ? out.size() - 2 : 0);
  return end == std::string::npos ? "" : out.substr(0, end + 1);
}

TEST_F(ReplayDirectory, OverSeveralThreadsEachCsvIsTheOneItsLogAloneGives) {
  const auto two = replay("--log " + path("logs").string() + " --out " + path("two").string() + " --threads 2");
  ASSERT_EQ(two.code, 0) << two.err;
  const auto one = replay("--log " + path("logs").string() + " --out " + path("one").string() + " --threads 1");
  ASSERT_EQ(one.code, 0) << one.err;
  EXPECT_EQ(without_total(two.out), without_total(one.out)) << "the lines per log, in the order of the names";
  EXPECT_NE(two.out.find("[4/4] d_half.log (candump)"), std::string::npos) << two.out;
  std::size_t csvs = 0;
  for (const auto& e : fs::directory_iterator(path("logs"))) {
    const std::string name = e.path().stem().string() + ".csv";
    const auto alone = replay("--log " + e.path().string() + " --out " + path("alone_" + name).string());
    ASSERT_EQ(alone.code, 0) << alone.err;
    const std::string bytes = slurp(path("alone_" + name));
    ASSERT_GT(bytes.size(), 1000u);
    EXPECT_TRUE(slurp(path("two") / name) == bytes) << name << ": two threads differ from the log alone";
    EXPECT_TRUE(slurp(path("one") / name) == bytes) << name << ": one thread differs from the log alone";
    ++csvs;
  }
  EXPECT_EQ(csvs, 4u);
  // The same frames in three formats: the same estimates.
  EXPECT_TRUE(slurp(path("two") / "a_candump.csv") == slurp(path("two") / "b_asc.csv"));
  EXPECT_TRUE(slurp(path("two") / "a_candump.csv") == slurp(path("two") / "c_blf.csv"));
}

TEST_F(ReplayDirectory, ABadLogIsOneLineNamingItAndNothingIsWritten) {
  TempDir bad;
  fs::create_directories(bad.path() / "logs");
  fs::copy_file(kLog, bad.path() / "logs/a.log");
  fs::copy_file(kLog, bad.path() / "logs/c.log");
  std::ofstream(bad.path() / "logs/b.blf") << "not a BLF at all, and no CAN log either\n";
  const fs::path out = bad.path() / "out";
  const auto r = replay("--log " + (bad.path() / "logs").string() + " --out " + out.string());
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("b.blf"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(out)) << "nothing written";
  for (const auto& e : fs::directory_iterator(bad.path())) EXPECT_EQ(e.path().filename(), "logs") << "a temporary left";

  fs::remove(bad.path() / "logs/b.blf");
  fs::copy_file(kLog, bad.path() / "logs/a.asc");  // a.log and a.asc would both write a.csv
  const auto twice = replay("--log " + (bad.path() / "logs").string() + " --out " + out.string());
  EXPECT_EQ(twice.code, 2) << twice.err;
  EXPECT_NE(twice.err.find("a.asc and a.log"), std::string::npos) << twice.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(ReplayDirectory, ConvertOfADirectoryIsItsFilesOneAtATime) {
  const auto all = run("convert --in " + path("logs").string() + " --out " + path("csvs").string(), dir_->path());
  ASSERT_EQ(all.code, 0) << all.err;
  for (const auto& e : fs::directory_iterator(path("logs"))) {
    const std::string name = e.path().stem().string() + ".csv";
    const auto alone = run("convert --in " + e.path().string() + " --out " + path("conv_" + name).string(), dir_->path());
    ASSERT_EQ(alone.code, 0) << alone.err;
    EXPECT_TRUE(slurp(path("csvs") / name) == slurp(path("conv_" + name))) << name;
  }
  const auto back = run("convert --in " + path("csvs").string() + " --out " + path("back").string(), dir_->path());
  ASSERT_EQ(back.code, 0) << back.err;
  const auto one = run("convert --in " + (path("csvs") / "a_candump.csv").string() + " --out " +
                           path("back_one.log").string(),
                       dir_->path());
  ASSERT_EQ(one.code, 0) << one.err;
  EXPECT_TRUE(slurp(path("back") / "a_candump.log") == slurp(path("back_one.log")));
}

}  // namespace
}  // namespace lptn::replay
