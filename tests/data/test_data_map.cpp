// The data map (data.toml) and --suggest-map, tried as a user would: a generated dump turned into
// the shapes real exports have (issue 29), each read without a map (refused, saying how to fix it),
// then through the map lptn proposes, saved beside the files unedited, to the calibration the
// canonical CSV gives.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "lptn_testing/run_lptn.hpp"
#include "lptn_testing/temp_dir.hpp"
#include "simulator/generate/generate.hpp"
#include "trainer/data/data_map.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/data/suggest_map.hpp"

namespace lptn::data {
namespace {

namespace fs = std::filesystem;
using testing::run;
using testing::slurp;
using testing::TempDir;

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::stringstream s(line);
  for (std::string cell; std::getline(s, cell, sep);) out.push_back(cell);
  if (!line.empty() && line.back() == sep) out.emplace_back();
  return out;
}

Csv read_csv(const fs::path& p) {
  Csv c;
  std::ifstream in(p);
  std::string line;
  std::getline(in, line);
  c.header = split(line, ',');
  while (std::getline(in, line)) {
    c.rows.push_back(split(line, ','));
    c.rows.back().resize(c.header.size());
  }
  return c;
}

std::size_t column(const Csv& c, const std::string& name) {
  for (std::size_t j = 0; j < c.header.size(); ++j)
    if (c.header[j] == name) return j;
  ADD_FAILURE() << "no column " << name;
  return 0;
}

void write_lines(const fs::path& p, const std::vector<std::string>& lines) {
  fs::create_directories(p.parent_path());
  std::ofstream out(p, std::ios::binary);
  for (const std::string& l : lines) out << l << '\n';
}

std::string join(const std::vector<std::string>& cells, char sep) {
  std::string out;
  for (std::size_t i = 0; i < cells.size(); ++i) out += (i ? std::string(1, sep) : "") + cells[i];
  return out;
}

// "2024-03-04T06:00:00.103+01:00" for `t` seconds (as written, 3 decimals) after 06:00 local time.
std::string iso_time(const std::string& t_text, double offset_s) {
  const double t = std::stod(t_text) + offset_s;
  auto ms = static_cast<long long>(std::llround(t * 1000.0));
  long long whole = ms >= 0 ? ms / 1000 : -((-ms + 999) / 1000);
  const long long frac = ms - whole * 1000;
  whole += 6 * 3600;  // 06:00 on the day
  const long long day = whole / 86400, rest = whole % 86400;
  char buf[64];
  std::snprintf(buf, sizeof buf, "2024-03-%02lldT%02lld:%02lld:%02lld.%03lld+01:00", 4 + day, rest / 3600, rest / 60 % 60,
                rest % 60, frac);
  return buf;
}

// A number written again in another unit: value * scale + offset, 9 significant digits.
std::string converted(const std::string& cell, double scale, double offset) {
  if (cell.empty()) return cell;
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", std::stod(cell) * scale + offset);
  return buf;
}

// The anonymous export's column names: Kanal_01, Kanal_02, ...
std::string strf_index(std::size_t i) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "Kanal_%02zu", i + 1);
  return buf;
}

struct Fleet {
  TempDir dir;
  fs::path data() const { return dir.path() / "fleet"; }
  fs::path motor() const { return data() / "motor.toml"; }
  std::vector<fs::path> cycles;
};

void generate(Fleet& f) {
  gen::GenerateOptions o;
  o.cycles = 3;
  o.seed = 5;
  o.min_duration_s = 900;
  o.max_duration_s = 1200;
  gen::generate(o, f.data());
  for (const auto& e : fs::directory_iterator(f.data()))
    if (e.path().extension() == ".csv") f.cycles.push_back(e.path());
  std::sort(f.cycles.begin(), f.cycles.end());
  ASSERT_EQ(f.cycles.size(), 3u);
}

std::map<std::string, double> parameters(const fs::path& calibration) {
  const nlohmann::json j = nlohmann::json::parse(slurp(calibration));
  std::map<std::string, double> out;
  for (const auto& p : j.at("parameters")) out[p.at("name")] = p.at("value");
  return out;
}

// The largest relative difference between two calibrations' parameters.
double parameter_difference(const fs::path& a, const fs::path& b) {
  const auto pa = parameters(a), pb = parameters(b);
  EXPECT_EQ(pa.size(), pb.size());
  double worst = 0;
  for (const auto& [name, v] : pa) {
    EXPECT_TRUE(pb.count(name)) << name;
    if (pb.count(name)) worst = std::max(worst, std::fabs(pb.at(name) - v) / std::max(std::fabs(v), 1e-12));
  }
  return worst;
}

// The largest difference between two dumps' resampled samples, cycle by cycle in order; the
// cycles' step counts must agree.
double sample_difference(const data::Dataset& a, const data::Dataset& b) {
  EXPECT_EQ(a.cycles.size(), b.cycles.size());
  double worst = 0;
  for (std::size_t i = 0; i < std::min(a.cycles.size(), b.cycles.size()); ++i) {
    EXPECT_EQ(a.cycles[i].steps, b.cycles[i].steps) << a.cycles[i].name;
    for (data::Channel c : data::kAllChannels) {
      const auto &x = a.cycles[i].samples[data::index_of(c)], &y = b.cycles[i].samples[data::index_of(c)];
      EXPECT_EQ(x.size(), y.size()) << a.cycles[i].name << " " << data::channel_name(c);
      for (std::size_t k = 0; k < std::min(x.size(), y.size()); ++k) {
        if (std::isnan(x[k]) != std::isnan(y[k])) return INFINITY;
        if (!std::isnan(x[k])) worst = std::max(worst, static_cast<double>(std::fabs(x[k] - y[k])));
      }
    }
  }
  return worst;
}

// Reads `dir` without a map (refused: exit 2, one line naming the file and the way out), proposes
// a map and saves it beside the files unedited, and calibrates through it.
struct ShapeRun {
  std::string refusal;  // what inspect said without a map
  std::string proposed;  // the data.toml --suggest-map printed
  fs::path calibration;
};

ShapeRun through_suggested_map(const Fleet& f, const fs::path& dir, const std::string& test_cycle,
                               const std::string& suggest_extra = "") {
  ShapeRun r;
  const fs::path scratch = dir.parent_path();
  const auto bare = run("inspect --data " + dir.string(), scratch);
  EXPECT_EQ(bare.code, 2) << bare.out << bare.err;
  EXPECT_EQ(std::count(bare.err.begin(), bare.err.end(), '\n'), 1) << bare.err;
  r.refusal = bare.err;
  const auto suggested = run("inspect --data " + dir.string() + " --suggest-map" + suggest_extra, scratch);
  EXPECT_EQ(suggested.code, 0) << suggested.err;
  r.proposed = suggested.out;
  {
    std::ofstream out(dir / "data.toml");
    out << suggested.out;
  }
  r.calibration = scratch / (dir.filename().string() + ".json");
  const auto cal = run("calibrate --data " + dir.string() + " --motor " + f.motor().string() + " --out " +
                           r.calibration.string() + " --test-cycles " + test_cycle + " --quiet",
                       scratch);
  EXPECT_EQ(cal.code, 0) << cal.out << cal.err;
  return r;
}

fs::path canonical_calibration(const Fleet& f, const fs::path& data, const std::string& name) {
  const fs::path out = f.dir.path() / (name + ".json");
  const auto r = run("calibrate --data " + data.string() + " --motor " + f.motor().string() + " --out " + out.string() +
                         " --test-cycles cycle_03_intercity --quiet",
                     f.dir.path());
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  return out;
}

TEST(ExportShapes, OneLongFileWithDateTimesIsCutIntoItsDrivesAndCalibratesAsTheCycleFiles) {
  Fleet f;
  generate(f);
  // One file for all drives, a date-time with a zone instead of time_s, half an hour between drives.
  std::vector<std::string> lines;
  double offset = 0;
  for (const fs::path& p : f.cycles) {
    const Csv c = read_csv(p);
    if (lines.empty()) {
      std::vector<std::string> h = c.header;
      h[0] = "Timestamp";
      lines.push_back(join(h, ','));
    }
    for (std::vector<std::string> row : c.rows) {
      row[0] = iso_time(row[0], offset);
      lines.push_back(join(row, ','));
    }
    offset += std::stod(c.rows.back()[0]) + 1800;
  }
  const fs::path dir = f.dir.path() / "iso";
  write_lines(dir / "logger_export.csv", lines);

  const ShapeRun r = through_suggested_map(f, dir, "logger_export-3");
  EXPECT_NE(r.refusal.find("logger_export.csv:1: column 'time_s': required column missing"), std::string::npos) << r.refusal;
  EXPECT_NE(r.refusal.find("--suggest-map"), std::string::npos) << r.refusal;
  EXPECT_NE(r.proposed.find("column = \"Timestamp\"\nformat = \"iso8601\""), std::string::npos) << r.proposed;
  EXPECT_NE(r.proposed.find("[split]\npause_s = "), std::string::npos) << r.proposed;

  // The drives, shell-safe names, each the very samples of its cycle file.
  data::LoadOptions options;
  const data::Dataset canonical = data::load_fleet_dump({f.data()}, options);
  const data::Dataset mapped = data::load_fleet_dump({dir}, options);
  ASSERT_EQ(mapped.cycles.size(), 3u);
  EXPECT_EQ(mapped.cycles[0].name, "logger_export-1");
  EXPECT_EQ(mapped.cycles[2].name, "logger_export-3");
  // Not bit for bit: a drive's times are read from its file's first whole second, so its grid lies
  // at other binary offsets than its cycle file's (t = 0.997 + k/10 against -0.003 + k/10): the
  // interpolated samples differ in their last float bits.
  EXPECT_LE(sample_difference(canonical, mapped), 1e-6);
  EXPECT_LE(parameter_difference(canonical_calibration(f, f.data(), "canonical"), r.calibration), 1e-9);
}

TEST(ExportShapes, ALoggersOwnNamesAndUnitsAreMappedAndConverted) {
  Fleet f;
  generate(f);
  // The logger's names, temperatures in kelvin (the air in degrees Fahrenheit), the airflow in l/s.
  const std::map<std::string, std::pair<std::string, std::pair<double, double>>> logger{
      {"time_s", {"Zeit_s", {1, 0}}},
      {"speed_rpm", {"n_Motor", {1, 0}}},
      {"torque_nm", {"M_Motor", {1, 0}}},
      {"current_a", {"I_Phase", {1, 0}}},
      {"frequency_hz", {"f_Stator", {1, 0}}},
      {"voltage_v", {"U_Motor", {1, 0}}},
      {"airflow_m3s", {"Q_Luft_l/s", {1000, 0}}},
      {"ambient_c", {"T_Umgebung_F", {1.8, 32}}},
      {"stator_winding_c", {"T_Wicklung_K", {1, 273.15}}},
      {"rotor_c", {"T_Rotor_K", {1, 273.15}}},
  };
  const fs::path dir = f.dir.path() / "names";
  for (const fs::path& p : f.cycles) {
    const Csv c = read_csv(p);
    std::vector<std::string> lines;
    std::vector<std::string> h;
    for (const std::string& n : c.header) h.push_back(logger.at(n).first);
    lines.push_back(join(h, ','));
    for (const auto& row : c.rows) {
      std::vector<std::string> out;
      for (std::size_t j = 0; j < row.size(); ++j) {
        const auto [scale, offset] = logger.at(c.header[j]).second;
        out.push_back(scale == 1 && offset == 0 ? row[j] : converted(row[j], scale, offset));
      }
      lines.push_back(join(out, ','));
    }
    write_lines(dir / p.filename(), lines);
  }

  const ShapeRun r = through_suggested_map(f, dir, "cycle_03_intercity");
  // Every missing column at once, in one line.
  for (const char* name : {"time_s", "speed_rpm", "current_a", "frequency_hz", "airflow_m3s", "ambient_c", "stator_winding_c"})
    EXPECT_NE(r.refusal.find(std::string("'") + name + "'"), std::string::npos) << name << ": " << r.refusal;
  EXPECT_NE(r.refusal.find("required columns missing"), std::string::npos) << r.refusal;
  for (const char* line : {"airflow_m3s = { column = \"Q_Luft_l/s\", unit = \"l/s\" }",
                           "ambient_c = { column = \"T_Umgebung_F\", unit = \"°F\" }",
                           "stator_winding_c = { column = \"T_Wicklung_K\", unit = \"K\" }",
                           "rotor_c = { column = \"T_Rotor_K\", unit = \"K\" }", "speed_rpm = { column = \"n_Motor\" }"})
    EXPECT_NE(r.proposed.find(line), std::string::npos) << line << "\n" << r.proposed;

  // The same samples but for the units' rounding (9 digits written, float kept).
  const data::Dataset canonical = data::load_fleet_dump({f.data()});
  const data::Dataset mapped = data::load_fleet_dump({dir});
  EXPECT_LE(sample_difference(canonical, mapped), 1e-4);
  EXPECT_LE(parameter_difference(canonical_calibration(f, f.data(), "canonical"), r.calibration), 1e-6);
}

TEST(ExportShapes, NaNCellsAndADropoutReadAsEmptyCellsAndTheDropoutIsOneWarning) {
  Fleet f;
  generate(f);
  // The canonical files with a 6-minute dropout of every column; the export writes NaN for every
  // empty cell.
  const fs::path with_gap = f.dir.path() / "gap", dir = f.dir.path() / "nan";
  for (const fs::path& p : f.cycles) {
    Csv c = read_csv(p);
    for (std::size_t k = 3000; k < 6600; ++k)
      for (std::size_t j = 1; j < c.header.size(); ++j) c.rows[k][j].clear();
    std::vector<std::string> plain{join(c.header, ',')}, nan{join(c.header, ',')};
    for (auto row : c.rows) {
      plain.push_back(join(row, ','));
      for (std::string& cell : row)
        if (cell.empty()) cell = "NaN";
      nan.push_back(join(row, ','));
    }
    write_lines(with_gap / p.filename(), plain);
    write_lines(dir / p.filename(), nan);
  }
  fs::copy_file(f.motor(), with_gap / "motor.toml");

  const ShapeRun r = through_suggested_map(f, dir, "cycle_03_intercity");
  EXPECT_NE(r.refusal.find(":2: column "), std::string::npos) << r.refusal;
  EXPECT_NE(r.refusal.find("'NaN'"), std::string::npos) << r.refusal;
  EXPECT_NE(r.refusal.find("missing"), std::string::npos) << r.refusal;
  EXPECT_NE(r.proposed.find("missing = [\"NaN\"]"), std::string::npos) << r.proposed;

  const data::Dataset gap = data::load_fleet_dump({with_gap});
  const data::Dataset mapped = data::load_fleet_dump({dir});
  EXPECT_EQ(sample_difference(gap, mapped), 0.0);
  // The dropout: one warning per file, naming every column it hit.
  for (const data::CycleReport& rep : mapped.reports) {
    std::size_t warnings = 0;
    for (const data::Finding& w : rep.findings) {
      if (w.severity != data::Finding::Severity::warning) continue;
      ++warnings;
      EXPECT_NE(w.message.find("columns 'speed_rpm', 'torque_nm', 'current_a'"), std::string::npos) << w.message;
      EXPECT_NE(w.message.find("'rotor_c': no sample for"), std::string::npos) << w.message;
    }
    EXPECT_EQ(warnings, 1u) << rep.name;
  }
  const fs::path gap_cal = f.dir.path() / "gap.json";
  const auto g = run("calibrate --data " + with_gap.string() + " --motor " + f.motor().string() + " --out " +
                         gap_cal.string() + " --test-cycles cycle_03_intercity --quiet",
                     f.dir.path());
  ASSERT_EQ(g.code, 0) << g.err;
  EXPECT_LE(parameter_difference(gap_cal, r.calibration), 1e-9);
}

TEST(ExportShapes, ASemicolonExportWithDecimalCommasAndACommentLineIsRead) {
  Fleet f;
  generate(f);
  const fs::path dir = f.dir.path() / "euro";
  for (const fs::path& p : f.cycles) {
    const Csv c = read_csv(p);
    std::vector<std::string> lines{"# Export TrainLogger 4.2; unit 0815; 2024-03-04", join(c.header, ';')};
    for (auto row : c.rows) {
      for (std::string& cell : row) std::replace(cell.begin(), cell.end(), '.', ',');
      lines.push_back(join(row, ';'));
    }
    write_lines(dir / p.filename(), lines);
  }
  const ShapeRun r = through_suggested_map(f, dir, "cycle_03_intercity");
  EXPECT_NE(r.refusal.find("comment = \"#\""), std::string::npos) << r.refusal;
  EXPECT_NE(r.proposed.find("separator = \";\"\ndecimal = \",\"\ncomment = \"#\""), std::string::npos) << r.proposed;
  EXPECT_EQ(sample_difference(data::load_fleet_dump({f.data()}), data::load_fleet_dump({dir})), 0.0);
  EXPECT_LE(parameter_difference(canonical_calibration(f, f.data(), "canonical"), r.calibration), 1e-9);
  // Read through its map, the export is as clean as the canonical files.
  const auto strict = run("inspect --data " + dir.string() + " --strict", f.dir.path());
  EXPECT_EQ(strict.code, 0) << strict.out << strict.err;
}

// Columns with no telling names: matched by their values where the values tell (a speed and a
// frequency by their ratio, temperatures by range and slowness, the air by its small spread);
// what they cannot tell apart without the motor file is said, not guessed.
TEST(SuggestMap, AnonymousColumnsAreMatchedByTheirValuesOrNamedAsUndecided) {
  Fleet f;
  generate(f);
  // Columns shuffled, named Kanal_01..09; time in milliseconds; airflow in m³/h.
  const std::vector<std::string> order{"rotor_c",     "current_a",    "stator_winding_c", "speed_rpm", "airflow_m3s",
                                       "frequency_hz", "torque_nm",   "ambient_c",        "voltage_v"};
  const fs::path dir = f.dir.path() / "anon";
  for (const fs::path& p : f.cycles) {
    const Csv c = read_csv(p);
    std::vector<std::string> h{"Zeitstempel_ms"};
    for (std::size_t i = 0; i < order.size(); ++i) h.push_back(strf_index(i));
    std::vector<std::string> lines{join(h, ',')};
    for (const auto& row : c.rows) {
      std::vector<std::string> out{std::to_string(std::llround(std::stod(row[0]) * 1000))};
      for (const std::string& name : order) {
        const std::string& cell = row[column(c, name)];
        out.push_back(name == "airflow_m3s" ? converted(cell, 3600, 0) : cell);
      }
      lines.push_back(join(out, ','));
    }
    write_lines(dir / p.filename(), lines);
  }
  const auto expect = [&](const std::string& proposed, const std::string& channel, std::size_t kanal) {
    EXPECT_NE(proposed.find(channel + " = { column = \"" + strf_index(kanal)), std::string::npos)
        << channel << "\n" << proposed;
  };
  // Without the motor file: current and voltage cannot be told from each other or the airflow.
  const auto bare = run("inspect --data " + dir.string() + " --suggest-map", f.dir.path());
  EXPECT_EQ(bare.code, 1) << bare.err;
  EXPECT_NE(bare.err.find("no column found for current_a (required)"), std::string::npos) << bare.err;
  EXPECT_NE(bare.out.find("format = \"milliseconds\""), std::string::npos) << bare.out;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const std::size_t at = bare.out.find("= { column = \"" + strf_index(i) + "\"");
    if (at == std::string::npos) continue;
    // Whatever it mapped, it mapped right.
    const std::size_t line = bare.out.rfind('\n', at) + 1;
    EXPECT_EQ(bare.out.substr(line, order[i].size() + 1), order[i] + " ") << bare.out.substr(line, at - line);
  }
  // With it: every column, the airflow's unit by the motor's nominal airflow.
  const auto with_motor =
      run("inspect --data " + dir.string() + " --motor " + f.motor().string() + " --suggest-map", f.dir.path());
  EXPECT_EQ(with_motor.code, 0) << with_motor.err;
  for (std::size_t i = 0; i < order.size(); ++i) expect(with_motor.out, order[i], i);
  EXPECT_NE(with_motor.out.find("unit = \"m³/h\""), std::string::npos) << with_motor.out;
}

TEST(DataMapFile, AnErrorNamesTheFileTheLineAndTheKey) {
  TempDir dir;
  const std::vector<std::pair<std::string, std::string>> cases{
      {"[columns]\nrotor_c = { column = \"T\", unit = \"Kelvin\" }\n", "bad.toml:2: key 'columns.rotor_c.unit': unknown unit 'Kelvin'"},
      {"[time]\ncolumn = \"t\"\nformt = \"iso8601\"\n", "bad.toml:3: key 'time.formt': unknown key (did you mean 'format'?)"},
      {"[columns]\nspeed_rpm = \"n\"\nfrequency_hz = \"n\"\n", "bad.toml:3: key 'columns.frequency_hz': column 'n' is already read as columns.speed_rpm"},
      {"[csv]\nseparator = \",\"\ndecimal = \",\"\n", "bad.toml:1: key 'csv.decimal': is the separator too"},
      {"[split]\npause_s = -5\n", "bad.toml:2: key 'split.pause_s': must be greater than zero"},
      {"[columns]\nrotor = \"T\"\n", "bad.toml:2: key 'columns.rotor': unknown key (did you mean 'rotor_c'?)"},
      {"[time\ncolumn = 1\n", "bad.toml:1: "},
  };
  write_lines(dir.path() / "c.csv", {"time_s,speed_rpm", "0,1"});
  for (const auto& [text, expected] : cases) {
    {
      std::ofstream out(dir.path() / "bad.toml");
      out << text;
    }
    const auto r = run("inspect --data " + (dir.path() / "c.csv").string() + " --map " + (dir.path() / "bad.toml").string(),
                       dir.path());
    EXPECT_EQ(r.code, 2) << text;
    EXPECT_NE(r.err.find(expected), std::string::npos) << text << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}

TEST(DataMapFile, WhatItWritesReadsBackEqual) {
  data::DataMap m;
  m.separator = '\t';
  m.decimal = ',';
  m.comment = "//";
  m.missing = {"NaN", "-", "\"quoted\""};
  m.time_column = "Zeit [ms]";
  m.time_format = data::TimeFormat::milliseconds;
  m.columns[data::index_of(data::Channel::rotor_c)] = data::ColumnSource{"T rotor \\ K", "K", 1, -273.15};
  m.columns[data::index_of(data::Channel::current_a)] = data::ColumnSource{"I", "", 0.001, 0.5};
  m.ignore = {"GPS", "lat,lon"};
  m.split_pause_s = 450.5;
  m.split_column = "trip";
  const data::DataMap back = data::parse_data_map(data::format_data_map(m, "a header\nover two lines"), "x.toml");
  EXPECT_EQ(back.separator, m.separator);
  EXPECT_EQ(back.decimal, m.decimal);
  EXPECT_EQ(back.comment, m.comment);
  EXPECT_EQ(back.missing, m.missing);
  EXPECT_EQ(back.time_column, m.time_column);
  EXPECT_EQ(back.time_format, m.time_format);
  EXPECT_EQ(back.ignore, m.ignore);
  EXPECT_EQ(back.split_pause_s, m.split_pause_s);
  EXPECT_EQ(back.split_column, m.split_column);
  for (data::Channel c : data::kAllChannels) {
    const auto &a = m.columns[data::index_of(c)], &b = back.columns[data::index_of(c)];
    ASSERT_EQ(a.has_value(), b.has_value()) << data::channel_name(c);
    if (!a) continue;
    EXPECT_EQ(a->column, b->column);
    EXPECT_EQ(a->scale, b->scale);
    EXPECT_EQ(a->offset, b->offset);
  }
}

TEST(DataMapFile, UnitsConvertToLptnsOwn) {
  const auto value = [](data::Channel c, const char* unit, double v) {
    const auto u = data::find_unit(c, unit);
    EXPECT_TRUE(u.has_value()) << unit;
    return u ? v * u->scale + u->offset : NAN;
  };
  EXPECT_NEAR(value(data::Channel::ambient_c, "°F", 212), 100, 1e-12);
  EXPECT_NEAR(value(data::Channel::ambient_c, "K", 273.15), 0, 1e-12);
  EXPECT_NEAR(value(data::Channel::speed_rpm, "rad/s", 2 * M_PI), 60, 1e-12);
  EXPECT_NEAR(value(data::Channel::speed_rpm, "Hz", 50), 3000, 1e-12);
  EXPECT_NEAR(value(data::Channel::airflow_m3s, "m³/h", 3600), 1, 1e-12);
  EXPECT_NEAR(value(data::Channel::airflow_m3s, "l/s", 700), 0.7, 1e-12);
  EXPECT_NEAR(value(data::Channel::airflow_m3s, "cfm", 2118.88), 1.0, 1e-5);
  EXPECT_NEAR(value(data::Channel::current_a, "kA", 0.115), 115, 1e-12);
  EXPECT_FALSE(data::find_unit(data::Channel::current_a, "K").has_value());  // a unit of another quantity
}

TEST(DataMapFile, DateTimesWithAndWithoutZone) {
  double t = 0;
  ASSERT_TRUE(data::parse_iso8601("1970-01-01T00:00:00Z", t));
  EXPECT_EQ(t, 0);
  ASSERT_TRUE(data::parse_iso8601("2024-03-04T06:00:00.125+01:00", t));
  EXPECT_EQ(t, 1709528400.125);
  ASSERT_TRUE(data::parse_iso8601("2024-03-04 05:00:00.125", t));  // no zone: as written
  EXPECT_EQ(t, 1709528400.125);
  ASSERT_TRUE(data::parse_iso8601("2024-03-04T00:30-0130", t));
  EXPECT_EQ(t, 1709517600);  // 02:00 UTC
  ASSERT_TRUE(data::parse_iso8601("2024-02-29T00:00:00Z", t));  // a leap day
  EXPECT_FALSE(data::parse_iso8601("2023-02-29T00:00:00Z", t));
  EXPECT_FALSE(data::parse_iso8601("2024-13-01T00:00:00Z", t));
  EXPECT_FALSE(data::parse_iso8601("2024-03-04T24:00:00Z", t));
  EXPECT_FALSE(data::parse_iso8601("2024-03-04T06:00:00.Z", t));
  EXPECT_FALSE(data::parse_iso8601("2024-03-04", t));
  EXPECT_FALSE(data::parse_iso8601("1709528400", t));
}

TEST(DataMapFile, ATripColumnCutsTheFileIntoShellSafeDrives) {
  TempDir dir;
  std::vector<std::string> lines{"t_ms;trip;n;I;f;Q;Ta;Ts"};
  for (int trip = 0; trip < 2; ++trip)
    for (int k = 0; k < 900; ++k)
      lines.push_back(std::to_string(trip * 2'000'000 + k * 100) + ";" + (trip ? "B 2" : "A/1") + ";1500;80;50,5;" +
                      "2520;59;" + std::to_string(300 + k / 100));
  write_lines(dir.path() / "export.csv", lines);
  write_lines(dir.path() / "data.toml",
              {"[csv]", "separator = \";\"", "decimal = \",\"", "[time]", "column = \"t_ms\"", "format = \"milliseconds\"",
               "[split]", "column = \"trip\"", "[columns]", "speed_rpm = \"n\"", "current_a = \"I\"", "frequency_hz = \"f\"",
               "airflow_m3s = { column = \"Q\", unit = \"m3/h\" }", "ambient_c = { column = \"Ta\", unit = \"degF\" }",
               "stator_winding_c = { column = \"Ts\", unit = \"K\" }"});
  const data::Dataset d = data::load_fleet_dump({dir.path()});
  ASSERT_EQ(d.cycles.size(), 2u);
  EXPECT_EQ(d.cycles[0].name, "export-A_1");
  EXPECT_EQ(d.cycles[1].name, "export-B_2");
  EXPECT_NEAR(d.cycles[0].at(data::Channel::airflow_m3s, 0), 0.7, 1e-6);
  EXPECT_NEAR(d.cycles[0].at(data::Channel::ambient_c, 0), 15, 1e-5);
  EXPECT_NEAR(d.cycles[1].at(data::Channel::stator_winding_c, 0), 26.85, 1e-4);
  EXPECT_NEAR(d.cycles[0].at(data::Channel::frequency_hz, 0), 50.5, 1e-6);
  EXPECT_NEAR(d.cycles[1].duration_s(), 89.9, 1e-9);
}

}  // namespace
}  // namespace lptn::data

namespace lptn::data {
namespace {

// `text`, as Markdown code. Appended piecewise: GCC 12 warns falsely (-Wrestrict) on "`" + std::string(...) at -O3.
std::string backquoted(std::string_view text) {
  std::string out(1, '`');
  out.append(text);
  out += '`';
  return out;
}

// docs/data-map.md's table of units is the reader's: every unit the reader takes is in its channel's row.
TEST(DataMapFile, TheDocumentedUnitsAreTheReadersUnits) {
  const std::string doc = testing::slurp(std::filesystem::path(LPTN_TEST_DATA_DIR) / "../../docs/data-map.md");
  ASSERT_FALSE(doc.empty());
  for (data::Channel c : data::kAllChannels) {
    const std::size_t table = doc.find("| channel | units |");
    ASSERT_NE(table, std::string::npos);
    const std::size_t name = doc.find(backquoted(data::channel_name(c)), table);
    ASSERT_NE(name, std::string::npos) << data::channel_name(c);
    const std::size_t row = doc.rfind('\n', name) + 1;
    const std::string line = doc.substr(row, doc.find('\n', row) - row);
    for (const data::UnitConversion& u : data::units_of(c))
      EXPECT_NE(line.find(backquoted(u.unit)), std::string::npos) << u.unit << " in " << line;
  }
}

}  // namespace
}  // namespace lptn::data

namespace lptn::data {
namespace {

// A spreadsheet export on Windows writes its header in Windows-1252 ("°" the single byte 0xB0).
// A data map is UTF-8 (TOML), so such a header is read as Latin-1: the map spells "°C", and the
// proposed map reads back and reads the file.
TEST(DataMapFile, AWindows1252HeaderIsNamedInUtf8) {
  testing::TempDir dir;
  std::vector<std::string> lines{"Zeit [s];n [1/min];I [A];f [Hz];Q [m\xB3/s];T_Luft [\xB0" "C];T_Wicklung [\xB0" "C]"};
  for (int k = 0; k < 600; ++k)
    lines.push_back(std::to_string(k) + ",0;" + std::to_string(1500 + k % 7) + ";" + std::to_string(80 + k % 5) +
                    ";50,5;0,7;15,0;" + std::to_string(40 + k / 60) + ",5");
  write_lines(dir.path() / "export.csv", lines);
  const data::MapSuggestion s = data::suggest_data_map({dir.path()});
  const std::string text = s.text();
  EXPECT_NE(text.find("stator_winding_c = { column = \"T_Wicklung [\xC2\xB0" "C]\" }"), std::string::npos) << text;
  EXPECT_NE(text.find("airflow_m3s = { column = \"Q [m\xC2\xB3/s]\" }"), std::string::npos) << text;
  {
    std::ofstream out(dir.path() / "data.toml");
    out << text;
  }
  const data::Dataset d = data::load_fleet_dump({dir.path()});
  ASSERT_EQ(d.cycles.size(), 1u);
  EXPECT_NEAR(d.cycles[0].at(data::Channel::stator_winding_c, 0), 40.5, 1e-6);
  EXPECT_NEAR(d.cycles[0].at(data::Channel::frequency_hz, 0), 50.5, 1e-6);
}

}  // namespace
}  // namespace lptn::data

namespace lptn::data {
namespace {

// pandas' DataFrame.to_csv: an unnamed index column first, date-times with a space and six decimals.
TEST(DataMapFile, APandasExportWithItsIndexColumnIsReadWithoutAWarning) {
  testing::TempDir dir;
  std::vector<std::string> lines{",datetime,speed_rpm,current_a,frequency_hz,airflow_m3s,ambient_c,stator_winding_c"};
  for (int k = 0; k < 900; ++k) {
    char t[64];
    std::snprintf(t, sizeof t, "2024-03-04 06:%02d:%02d.%06d", k / 600, (k / 10) % 60, (k % 10) * 100000);
    lines.push_back(std::to_string(k) + "," + t + ",1500.0,80.0,50.5,0.7,15.0," + std::to_string(40 + k / 100) + ".5");
  }
  write_lines(dir.path() / "export.csv", lines);
  const data::MapSuggestion s = data::suggest_data_map({dir.path()});
  EXPECT_TRUE(s.problems.empty()) << s.text();
  EXPECT_EQ(s.map.ignore, std::vector<std::string>{""});
  EXPECT_EQ(s.map.time_format, data::TimeFormat::iso8601);
  {
    std::ofstream out(dir.path() / "data.toml");
    out << s.text();
  }
  const data::Dataset d = data::load_fleet_dump({dir.path()});
  ASSERT_EQ(d.cycles.size(), 1u);
  EXPECT_EQ(d.warning_count(), 0u);
  EXPECT_NEAR(d.cycles[0].duration_s(), 89.9, 1e-9);
}

}  // namespace
}  // namespace lptn::data

namespace lptn::data {
namespace {

// The index pandas writes (0, 1, 2...) increases as a time column does: with no column named like a
// time, the time is still the column that is one, never the unnamed index (fuzz_data_map found it).
TEST(SuggestMap, APandasIndexIsNeverTakenForTheTime) {
  testing::TempDir dir;
  std::vector<std::string> lines{",elapsed,speed_rpm,current_a,frequency_hz,airflow_m3s,ambient_c,stator_winding_c"};
  for (int k = 0; k < 900; ++k)
    lines.push_back(std::to_string(k) + "," + std::to_string(k / 10) + "." + std::to_string(k % 10) +
                    ",1500.0,80.0,50.5,0.7,15.0," + std::to_string(40 + k / 100) + ".5");
  write_lines(dir.path() / "export.csv", lines);
  const data::MapSuggestion s = data::suggest_data_map({dir.path()});
  EXPECT_EQ(s.map.time_column, "elapsed") << s.text();
  EXPECT_EQ(s.map.ignore, std::vector<std::string>{""});
  EXPECT_NO_THROW(data::parse_data_map(s.text(), "proposed.toml"));
}

}  // namespace
}  // namespace lptn::data
