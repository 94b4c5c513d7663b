// The semantic bad-input suite: inputs that parse but mean something else than lptn takes them
// to (temperatures in kelvin, a motor file whose values its own nameplate makes implausible, a
// misspelt key, a file of another kind, an output nobody can write). Every input is made here from
// the synthetic plant (lptn generate) and changed the way a user's file would be wrong; every case
// runs the lptn program and asserts its exit code and its message, which is one line, never a
// crash nor a third-party library's words.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "lptn_testing/run_lptn.hpp"
#include "lptn_testing/temp_dir.hpp"

namespace lptn::cli {
namespace {

namespace fs = std::filesystem;
using testing::Result;

// One generated dump for the whole suite: two short cycles of the example motor.
class SemanticInput : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir;
    const Result g = testing::run("generate --out " + dump().string() + " --cycles 2 --seed 3 --minutes-min 6 --minutes-max 8",
                                  dir_->path());
    ASSERT_EQ(g.code, 0) << g.err;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path dump() { return dir_->path() / "dump"; }
  static fs::path motor() { return dump() / "motor.toml"; }
  static fs::path first_cycle() { return dump() / "cycle_01_suburban.csv"; }

  Result run(const std::string& args) { return testing::run(args, scratch_.path()); }
  fs::path scratch(const std::string& name) const { return scratch_.path() / name; }

  static testing::TempDir* dir_;
  testing::TempDir scratch_;
};
testing::TempDir* SemanticInput::dir_ = nullptr;

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

// The cycle CSV `in` with every value of `column` replaced by f(value), written to `out`.
void rewrite_column(const fs::path& in, const fs::path& out, const std::string& column,
                    const std::function<double(double)>& f) {
  std::ifstream src(in);
  std::ofstream dst(out);
  std::string line;
  std::getline(src, line);
  const std::vector<std::string> header = split(line);
  const auto at = std::find(header.begin(), header.end(), column);
  ASSERT_NE(at, header.end()) << column;
  const auto index = static_cast<std::size_t>(at - header.begin());
  dst << line << '\n';
  while (std::getline(src, line)) {
    std::vector<std::string> cells = split(line);
    if (index < cells.size() && !cells[index].empty()) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.2f", f(std::stod(cells[index])));
      cells[index] = buf;
    }
    for (std::size_t i = 0; i < cells.size(); ++i) dst << (i ? "," : "") << cells[i];
    dst << '\n';
  }
}

// The median of a column of a cycle CSV.
double column_median(const fs::path& csv, const std::string& column) {
  std::ifstream src(csv);
  std::string line;
  std::getline(src, line);
  const std::vector<std::string> header = split(line);
  const auto index = static_cast<std::size_t>(std::find(header.begin(), header.end(), column) - header.begin());
  std::vector<double> v;
  while (std::getline(src, line)) {
    const std::vector<std::string> cells = split(line);
    if (index < cells.size() && !cells[index].empty()) v.push_back(std::stod(cells[index]));
  }
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// `motor` with its line starting "KEY = " changed: to "KEY = value", or (rename) to "value = ..."
// (a misspelt key). Returns the new file's 1-based line of that key.
int edit_motor(const fs::path& motor, const fs::path& out, const std::string& key, const std::string& value,
               bool rename = false) {
  std::ifstream src(motor);
  std::ofstream dst(out);
  std::string line;
  int n = 0, found = 0;
  while (std::getline(src, line)) {
    ++n;
    if (line.rfind(key + " = ", 0) == 0) {
      found = n;
      line = rename ? value + line.substr(key.size()) : key + " = " + value;
    }
    dst << line << '\n';
  }
  return found;
}

// A bad-input failure as the house has it: exit code 2, one line on stderr, "lptn: error: ..."
// holding `expected`, and nothing on the way from a crash or a library.
void expect_bad_input(const Result& r, const std::string& expected) {
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("lptn: error: ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
}

// A run that went through, whatever it warned of.
void expect_ran(const Result& r) {
  EXPECT_EQ(r.code, 0) << r.err;
  for (const char* crash : {"terminate", "Segmentation", "Aborted", "error:"})
    EXPECT_EQ(r.err.find(crash), std::string::npos) << r.err;
}

std::string inspect_args(const fs::path& data) { return "inspect --data " + data.string(); }

TEST_F(SemanticInput, AmbientInKelvinIsRefusedAtItsFirstReading) {
  const fs::path csv = scratch("cycle.csv");
  rewrite_column(first_cycle(), csv, "ambient_c", [](double c) { return c + 273.15; });
  const Result r = run(inspect_args(csv));
  expect_bad_input(r, csv.string() + ":2: column 'ambient_c': '");
  EXPECT_NE(r.err.find("is outside the physically possible -60..70"), std::string::npos) << r.err;
}

// A sensor column in kelvin lies within the winding's -60..400 degC: only its level against the air
// tells it, and the message says both (medians over the file, rounded).
void expect_kelvin_refused(const Result& r, const fs::path& csv, const std::string& column, double sensor_k,
                           double ambient_c) {
  char expected[200];
  std::snprintf(expected, sizeof expected, "%s:1: column '%s': kelvin? this column reads %.0f while ambient_c reads %.0f",
                csv.string().c_str(), column.c_str(), sensor_k, ambient_c);
  expect_bad_input(r, expected);
  EXPECT_NE(r.err.find("the contract is degrees Celsius"), std::string::npos) << r.err;
}

TEST_F(SemanticInput, WindingInKelvinWithAmbientInCelsiusIsRefused) {
  const fs::path csv = scratch("cycle.csv");
  rewrite_column(first_cycle(), csv, "stator_winding_c", [](double c) { return c + 273.15; });
  const double sensor = column_median(csv, "stator_winding_c"), ambient = column_median(csv, "ambient_c");
  expect_kelvin_refused(run(inspect_args(csv)), csv, "stator_winding_c", sensor, ambient);
  // The same from every command that loads the dump, before any output is made.
  const Result s = run("simulate --data " + csv.string() + " --motor " + motor().string() + " --out " +
                       scratch("sim").string());
  expect_kelvin_refused(s, csv, "stator_winding_c", sensor, ambient);
  EXPECT_FALSE(fs::exists(scratch("sim")));
}

TEST_F(SemanticInput, RotorInKelvinIsRefused) {
  const fs::path csv = scratch("cycle.csv");
  rewrite_column(first_cycle(), csv, "rotor_c", [](double c) { return c + 273.15; });
  expect_kelvin_refused(run(inspect_args(csv)), csv, "rotor_c", column_median(csv, "rotor_c"),
                        column_median(csv, "ambient_c"));
}

TEST_F(SemanticInput, HotButRealMotorIsNotRefused) {
  // The winding's rise over the air tripled and 120 K more: medians ~160 K above ambient, peaks
  // past 200 degC, as a motor at its insulation class's limit would read.
  const fs::path csv = scratch("cycle.csv");
  const double ambient = column_median(first_cycle(), "ambient_c");
  rewrite_column(first_cycle(), csv, "stator_winding_c", [&](double c) { return ambient + 3 * (c - ambient) + 120; });
  ASSERT_GT(column_median(csv, "stator_winding_c") - ambient, 150);
  const Result r = run(inspect_args(csv));
  expect_ran(r);
  EXPECT_EQ(r.err, "");
}

// inspect --motor's JSON: the motor file's findings.
nlohmann::json motor_findings(const Result& r) {
  EXPECT_EQ(r.code, 0) << r.err;
  return nlohmann::json::parse(r.out).at("motor_findings");
}

// "lo..hi UNIT (...)" -> {lo, hi}
std::pair<double, double> range_of(const std::string& plausible) {
  const std::size_t dots = plausible.find("..");
  return {std::stod(plausible.substr(0, dots)), std::stod(plausible.substr(dots + 2))};
}

TEST_F(SemanticInput, ThePlantsOwnMotorIsPlausible) {
  const Result r = run(inspect_args(dump()) + " --motor " + motor().string() + " --json");
  EXPECT_EQ(motor_findings(r).size(), 0u) << r.out;
  const Result text = run(inspect_args(dump()) + " --motor " + motor().string());
  EXPECT_NE(text.out.find("the motor file's values against its nameplate: all plausible"), std::string::npos);
}

TEST_F(SemanticInput, StatorResistanceOf80OhmIsFlaggedWithItsRange) {
  const fs::path m = scratch("motor.toml");
  const int line = edit_motor(motor(), m, "stator_resistance_20c_ohm", "80.0");
  const nlohmann::json f = motor_findings(run(inspect_args(dump()) + " --motor " + m.string() + " --json"));
  ASSERT_EQ(f.size(), 1u) << f.dump();
  EXPECT_EQ(f[0]["key"], "electrical.stator_resistance_20c_ohm");
  EXPECT_EQ(f[0]["value"], 80.0);
  EXPECT_EQ(f[0]["line"], line);
  // 3 x 80 ohm x (115 A)^2 = 3.17 MW against the nameplate's 310 kW.
  EXPECT_NE(f[0]["message"].get<std::string>().find("gives 3.2 MW of copper loss at rated current (rated power 310 kW)"),
            std::string::npos)
      << f[0]["message"];
  // The range holds the plant's own resistance and not the typo.
  const auto [lo, hi] = range_of(f[0]["plausible"]);
  EXPECT_LT(lo, 0.14);
  EXPECT_GT(hi, 0.14);
  EXPECT_LT(hi, 80);
  // The text report prints it as one warning line, with the file and line.
  const Result text = run(inspect_args(dump()) + " --motor " + m.string());
  EXPECT_NE(text.out.find("  warning: " + m.string() + ":" + std::to_string(line) +
                          ": key 'electrical.stator_resistance_20c_ohm': stator_resistance_20c_ohm = 80 gives"),
            std::string::npos)
      << text.out;
  // simulate repeats it, and says it is why the temperatures ran away.
  const Result s = run("simulate --data " + dump().string() + " --motor " + m.string());
  expect_ran(s);
  EXPECT_NE(s.err.find("lptn: warning: " + m.string() + ":" + std::to_string(line)), std::string::npos) << s.err;
  EXPECT_NE(s.err.find("the model's temperatures run away"), std::string::npos) << s.err;
}

TEST_F(SemanticInput, TemperatureCoefficientTypedAsAPercentIsFlagged) {
  const fs::path m = scratch("motor.toml");
  edit_motor(motor(), m, "stator_resistance_alpha_per_k", "0.393");
  const nlohmann::json f = motor_findings(run(inspect_args(dump()) + " --motor " + m.string() + " --json"));
  ASSERT_EQ(f.size(), 1u) << f.dump();
  EXPECT_EQ(f[0]["key"], "electrical.stator_resistance_alpha_per_k");
  EXPECT_NE(f[0]["message"].get<std::string>().find("looks like a percent per kelvin typed as a fraction"),
            std::string::npos)
      << f[0]["message"];
  const auto [lo, hi] = range_of(f[0]["plausible"]);
  EXPECT_LT(lo, 0.00393);  // copper
  EXPECT_GT(hi, 0.00403);  // aluminium
}

TEST_F(SemanticInput, CapacityOf60JoulePerKelvinIsFlagged) {
  const fs::path m = scratch("motor.toml");
  edit_motor(motor(), m, "capacitance_stator_winding_j_per_k", "60.0");
  const nlohmann::json f = motor_findings(run(inspect_args(dump()) + " --motor " + m.string() + " --json"));
  ASSERT_EQ(f.size(), 1u) << f.dump();
  EXPECT_EQ(f[0]["key"], "thermal.capacitance_stator_winding_j_per_k");
  EXPECT_NE(f[0]["plausible"].get<std::string>().find("kJ/K.."), std::string::npos) << f[0]["plausible"];
  // Flagged, not refused: the model still runs.
  expect_ran(run("simulate --data " + dump().string() + " --motor " + m.string()));
}

TEST_F(SemanticInput, RatedPowerInKilowattsComesFirstAmongWhatItDrags) {
  // 310 for 310e3: every range scaled by rated power moves with it; the cause is named first.
  const fs::path m = scratch("motor.toml");
  ASSERT_GT(edit_motor(motor(), m, "rated_power_w", "310.0"), 0);
  const nlohmann::json f = motor_findings(run(inspect_args(dump()) + " --motor " + m.string() + " --json"));
  ASSERT_GT(f.size(), 1u) << f.dump();
  EXPECT_EQ(f[0]["key"], "nameplate.rated_power_w");
  // "151 kW..378 kW" (sqrt(3) x 1900 V x 115 A x 0.4..1): the plant's 310 kW inside, the typo not.
  const std::string plausible = f[0]["plausible"];
  ASSERT_EQ(plausible.find(" kW.."), plausible.find(" kW")) << plausible;
  const auto [lo_kw, hi_kw] = range_of(plausible);
  EXPECT_LT(lo_kw, 310);
  EXPECT_GT(hi_kw, 310);
  EXPECT_GT(lo_kw * 1e3, 310.0);
}

TEST_F(SemanticInput, MisspeltKeyGetsDidYouMean) {
  const fs::path m = scratch("motor.toml");
  const int line = edit_motor(motor(), m, "stator_resistance_20c_ohm", "stator_resistence_20c_ohm", true);
  const Result r = run("simulate --data " + dump().string() + " --motor " + m.string());
  EXPECT_EQ(r.err, "lptn: error: " + m.string() + ":" + std::to_string(line) +
                       ": key 'electrical.stator_resistence_20c_ohm': unknown key (did you mean "
                       "'stator_resistance_20c_ohm'?)\n");
  EXPECT_EQ(r.code, 2);
  // An optional key misspelt is unknown too.
  const int beta = edit_motor(motor(), m, "iron_beta", "iron_betta", true);
  expect_bad_input(run("simulate --data " + dump().string() + " --motor " + m.string()),
                   m.string() + ":" + std::to_string(beta) + ": key 'losses.iron_betta': unknown key (did you mean 'iron_beta'?)");
  // And a parameter's table.
  std::ifstream src(motor());
  std::string text((std::istreambuf_iterator<char>(src)), {});
  const std::size_t at = text.find("[parameters.lambda_12s]");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 23, "[parameters.lambda_12z]");
  std::ofstream(m) << text;
  expect_bad_input(run("simulate --data " + dump().string() + " --motor " + m.string()),
                   "key 'parameters.lambda_12z': unknown parameter (did you mean 'lambda_12s'?)");
}

TEST_F(SemanticInput, MisnamedColumnIsRepeatedBySimulate) {
  const fs::path dir = scratch("data");
  fs::create_directories(dir);
  std::ifstream src(first_cycle());
  std::string text((std::istreambuf_iterator<char>(src)), {});
  text.replace(text.find("rotor_c"), 7, "roter_c");
  std::ofstream(dir / "cycle.csv") << text;
  const Result r = run("simulate --data " + dir.string() + " --motor " + motor().string());
  expect_ran(r);
  EXPECT_NE(r.err.find("lptn: warning: " + (dir / "cycle.csv").string() +
                       ":1: column 'roter_c': unknown column; ignored (did you mean 'rotor_c'?)\n"),
            std::string::npos)
      << r.err;
}

TEST_F(SemanticInput, AnotherPoleCountIsRepeatedBySimulate) {
  const fs::path m = scratch("motor.toml");
  edit_motor(motor(), m, "pole_pairs", "3");
  const Result r = run("simulate --data " + dump().string() + " --motor " + m.string());
  expect_ran(r);
  EXPECT_NE(r.err.find("lptn: warning: cycle cycle_01_suburban"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("frequency_hz differs from speed_rpm * 3 / 60"), std::string::npos) << r.err;
}

// A calibration made for a motor of three pole pairs (this motor's calibration with its kept
// motor's pole_pairs changed) replays a log of this two-pole-pair motor: the estimates look like
// any others, so the warning is what tells. The motor's own calibration replays the same log
// without it.
TEST_F(SemanticInput, ReplayOfAnotherMotorsLogWithThisCalibrationSaysSo) {
  const fs::path log = scratch("drive.log"), own = scratch("own.json"), other = scratch("other.json");
  ASSERT_EQ(run("convert --in " + first_cycle().string() + " --out " + log.string()).code, 0);
  const Result c = run("calibrate --method lm --data " + dump().string() + " --motor " + motor().string() + " --out " +
                       own.string());
  // Two short cycles pin little (it may be written as failed): what replay says of the motor is the question.
  ASSERT_TRUE(c.code == 0 || c.code == 3 || c.code == 4) << c.err;
  {
    std::ifstream in(own);
    nlohmann::json j = nlohmann::json::parse(in);
    ASSERT_EQ(j["motor"]["constants"]["nameplate"]["pole_pairs"], 2);
    j["motor"]["constants"]["nameplate"]["pole_pairs"] = 3;
    std::ofstream(other) << j.dump(2);
  }
  for (const fs::path& cal : {other, own}) {
    const Result r = run("replay --quiet --log " + log.string() + " --calibration " + cal.string() + " --out " +
                         scratch(cal.stem().string() + ".csv").string());
    EXPECT_EQ(r.code, 0) << r.err;
    const bool warned = r.err.find("lptn: warning: cycle drive.log (" + log.string() +
                                   "): frequency_hz differs from speed_rpm * 3 / 60") != std::string::npos;
    EXPECT_EQ(warned, cal == other) << r.err;
    if (cal == other) {
      EXPECT_NE(r.err.find("(the motor of " + cal.string()), std::string::npos) << r.err;
    } else {
      // Nothing about the motor; only, where the short dump left it not ok, the calibration's status.
      std::istringstream lines(r.err);
      for (std::string line; std::getline(lines, line);)
        if (line.find("warning") != std::string::npos) {
          EXPECT_EQ(line.rfind("lptn: warning: " + cal.string() + ": status " + (c.code == 4 ? "failed" : "warnings"), 0), 0u)
              << line;
        }
    }
  }
}

// replay checks what the log sent against the calibration's nameplate as the ticks go by
// (data::NameplateCheck fed by replay_to_csv with the last values received); inspect --log checks
// the same log, decoded as convert would and resampled to the model's grid, against a motor file of
// the same nameplate. A nameplate this log breaks every way (three pole pairs, 10 A and 100 V
// rated): both find the same three things at the same share of the drive. The model itself never
// sees the currents and voltages beyond that nameplate's plausible ranges (conditioning replaces
// them), so replay also says which inputs did not reach the model as sent.
TEST_F(SemanticInput, ReplayChecksTheLogAgainstTheNameplateAsInspectDoes) {
  const fs::path log = scratch("np.log"), cal = scratch("np.json"), m = scratch("np.toml");
  ASSERT_EQ(run("convert --in " + first_cycle().string() + " --out " + log.string()).code, 0);
  const Result c = run("calibrate --method lm --data " + dump().string() + " --motor " + motor().string() + " --out " +
                       cal.string() + " --force");
  ASSERT_TRUE(c.code == 0 || c.code == 3 || c.code == 4) << c.err;
  const std::vector<std::pair<std::string, std::string>> nameplate = {
      {"pole_pairs", "3"}, {"rated_current_a", "10.0"}, {"magnetizing_current_a", "5.0"}, {"rated_voltage_v", "100.0"}};
  {
    std::ifstream in(cal);
    nlohmann::json j = nlohmann::json::parse(in);
    nlohmann::json& constants = j["motor"]["constants"];
    for (const auto& [key, value] : nameplate)
      (key == "magnetizing_current_a" ? constants["electrical"] : constants["nameplate"])[key] = nlohmann::json::parse(value);
    std::ofstream(cal) << j.dump(2);
    fs::path from = motor();
    for (std::size_t i = 0; i < nameplate.size(); ++i) {
      const fs::path to = scratch("np-" + std::to_string(i) + ".toml");
      ASSERT_GT(edit_motor(from, to, nameplate[i].first, nameplate[i].second), 0) << nameplate[i].first;
      from = to;
    }
    fs::copy_file(from, m, fs::copy_options::overwrite_existing);
  }
  const Result r = run("replay --quiet --log " + log.string() + " --calibration " + cal.string() + " --out " +
                       scratch("np.csv").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const Result i = run("inspect --log " + log.string() + " --motor " + m.string());
  // Each check's finding: its share of the drive in per cent, from "at N of M steps".
  const auto share = [](const std::string& text, const std::string& check) {
    const std::size_t at = text.find(check);
    if (at == std::string::npos) return -1.0;
    unsigned long n = 0, of = 0;
    const std::size_t counts = text.find(" at ", at);
    if (counts == std::string::npos || std::sscanf(text.c_str() + counts, " at %lu of %lu", &n, &of) != 2 || of == 0)
      return -2.0;
    return 100.0 * static_cast<double>(n) / static_cast<double>(of);
  };
  const std::string inspected = i.out + i.err;
  for (const char* check : {"current_a above 4x rated (10 A)", "voltage_v above 1.3x rated (100 V)",
                            "frequency_hz differs from speed_rpm * 3 / 60"}) {
    const double replayed = share(r.err, check), expected = share(inspected, check);
    EXPECT_GT(expected, 1.0) << check << "\n" << inspected;
    EXPECT_NEAR(replayed, expected, 0.5) << check << "\n" << r.err << "\n" << inspected;
  }
  EXPECT_NE(r.err.find("(the motor of " + cal.string()), std::string::npos) << r.err;
  for (const char* input : {"current", "voltage"})
    EXPECT_NE(r.err.find(log.string() + ": input " + input + " did not reach the model as sent: implausible (outside 0 .. "),
              std::string::npos)
        << input << "\n" << r.err;
}

// A stator winding sensor that falls silent halfway through the drive: the estimates of the
// second half are the model's alone, and replay says so (the CSV's masks say it row by row), with
// the share of the rows, while the first half of the same log alone gives no such line.
TEST_F(SemanticInput, ReplaySaysWhenASensorFallsSilent) {
  const Result c = run("calibrate --method lm --data " + dump().string() + " --motor " + motor().string() + " --out " +
                       scratch("silent.json").string() + " --force");
  ASSERT_TRUE(c.code == 0 || c.code == 3 || c.code == 4) << c.err;
  std::vector<std::string> lines;
  {
    std::ifstream in(first_cycle());
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  ASSERT_GT(lines.size(), 1000u);
  const std::vector<std::string> header = split(lines[0]);
  const auto column = static_cast<std::size_t>(std::find(header.begin(), header.end(), "stator_winding_c") - header.begin());
  ASSERT_LT(column, header.size());
  const std::size_t half = lines.size() / 2;
  const fs::path silent = scratch("silent.csv"), first_half = scratch("first_half.csv");
  {
    std::ofstream all(silent), head(first_half);
    for (std::size_t k = 0; k < lines.size(); ++k) {
      std::vector<std::string> cells = split(lines[k]);
      if (k >= half && column < cells.size()) cells[column].clear();
      std::string row;
      for (std::size_t i = 0; i < cells.size(); ++i) row += (i ? "," : "") + cells[i];
      all << row << '\n';
      if (k < half) head << row << '\n';
    }
  }
  for (const fs::path& csv : {silent, first_half}) {
    const fs::path log = scratch(csv.stem().string() + ".log");
    ASSERT_EQ(run("convert --in " + csv.string() + " --out " + log.string()).code, 0);
    const Result r = run("replay --quiet --log " + log.string() + " --calibration " + scratch("silent.json").string() +
                         " --out " + scratch(csv.stem().string() + "-estimates.csv").string());
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string said = log.string() + ": input stator_sensor did not reach the model as sent: stale (no good value "
                                            "within its timeout) at ";
    const std::size_t at = r.err.find(said);
    if (csv == first_half) {
      EXPECT_EQ(r.err.find("did not reach the model"), std::string::npos) << r.err;
      continue;
    }
    ASSERT_NE(at, std::string::npos) << r.err;
    unsigned long n = 0, rows = 0;
    ASSERT_EQ(std::sscanf(r.err.c_str() + at + said.size(), "%lu of %lu rows", &n, &rows), 2) << r.err;
    EXPECT_NEAR(static_cast<double>(n) / static_cast<double>(rows), 0.5, 0.02) << r.err;
    EXPECT_NE(r.err.find("those rows went without its readings", at), std::string::npos) << r.err;
  }
}

TEST_F(SemanticInput, CalibrationGivenAsMotorIsNamedForWhatItIs) {
  // Told by content, not by name: the calibration is called .toml here.
  const fs::path cal = scratch("cal.toml");
  std::ofstream(cal) << "\n  {\"format_version\": 3, \"created_utc\": \"2024-01-01T00:00:00Z\", \"motor\": {}, "
                        "\"parameters\": [], \"metrics\": {}}\n";
  const Result r = run("simulate --data " + dump().string() + " --motor " + cal.string());
  EXPECT_EQ(r.err, "lptn: error: " + cal.string() +
                       " is a calibration file (JSON), not a motor file (TOML): give it as --calibration\n");
  EXPECT_EQ(r.code, 2);

  const fs::path fleet = scratch("fleet.json");
  std::ofstream(fleet) << "{\"format_version\": 1, \"pooled\": {}, \"fleet\": {}, \"motors\": {}}\n";
  expect_bad_input(run("inspect --data " + dump().string() + " --motor " + fleet.string()),
                   fleet.string() + " is a fleet calibration (JSON), not a motor file (TOML)");
  expect_bad_input(run("simulate --data " + dump().string() + " --motor " + first_cycle().string()),
                   first_cycle().string() + " is a fleet-dump cycle (CSV), not a motor file (TOML): give it as --data");
}

TEST_F(SemanticInput, OutputIntoAMissingDirectoryFailsAtOnce) {
  const fs::path out = scratch("nosuchdir") / "x";
  const auto start = std::chrono::steady_clock::now();
  const Result r = run("simulate --data " + dump().string() + " --motor " + motor().string() + " --out " + out.string());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.err, "lptn: error: --out " + out.string() + ": directory '" + out.parent_path().string() +
                       "' does not exist\n");
  EXPECT_EQ(r.code, 2);
  EXPECT_LT(seconds, 1.0);
  expect_bad_input(run("generate --out " + out.string() + " --cycles 1"), "directory '" + out.parent_path().string() + "' does not exist");
  expect_bad_input(run("convert --in " + first_cycle().string() + " --out " + out.string() + ".log"),
                   "directory '" + out.parent_path().string() + "' does not exist");
}

TEST_F(SemanticInput, MissingInputIsSaidBeforeAnExistingOutput) {
  const fs::path out = scratch("sim");
  fs::create_directories(out);
  std::ofstream(out / "metrics.json") << "{}\n";
  const Result r = run("simulate --data " + scratch("nosuch").string() + " --motor " + motor().string() + " --out " +
                       out.string());
  EXPECT_EQ(r.err, "lptn: error: --data " + scratch("nosuch").string() + ": no such file or directory\n");
  EXPECT_EQ(r.code, 2);
  expect_bad_input(run("simulate --data " + dump().string() + " --motor " + motor().string() + " --out " + out.string()),
                   out.string() + ": exists (use --force to replace it)");
}

}  // namespace
}  // namespace lptn::cli
