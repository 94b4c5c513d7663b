// Every input the data contract calls an error: DataError naming file, line and column.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test_util.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn::data {
namespace {

using test::TempDir;

const std::string kHeader =
    "time_s,speed_rpm,torque_nm,current_a,frequency_hz,voltage_v,airflow_m3s,ambient_c,stator_winding_c\n";
const std::string kRow0 = "0,1000,500,100,33.3,1000,1.5,20,40\n";
const std::string kRow1 = "0.1,1000,500,100,33.3,1000,1.5,20,40\n";
const std::string kRow2 = "0.2,1000,500,100,33.3,1000,1.5,20,40\n";

struct BadInput {
  std::string what;
  std::string text;
  int line;
  std::string column;  // empty: no column involved
};

std::vector<BadInput> bad_inputs() {
  return {
      {"non-numeric cell", kHeader + kRow0 + "0.1,1000,500,abc,33.3,1000,1.5,20,40\n", 3, "current_a"},
      {"trailing garbage", kHeader + kRow0 + kRow1 + "0.2,1000,500,100,33.3x,1000,1.5,20,40\n", 4, "frequency_hz"},
      {"hex number", kHeader + kRow0 + "0.1,0x10,500,100,33.3,1000,1.5,20,40\n", 3, "speed_rpm"},
      {"two signs", kHeader + kRow0 + "0.1,+-5,500,100,33.3,1000,1.5,20,40\n", 3, "speed_rpm"},
      {"nan text", kHeader + "0,nan,500,100,33.3,1000,1.5,20,40\n", 2, "speed_rpm"},
      {"NaN text", kHeader + kRow0 + "0.1,1000,500,100,33.3,1000,1.5,20,NaN\n", 3, "stator_winding_c"},
      {"inf text", kHeader + kRow0 + kRow1 + "0.2,1000,inf,100,33.3,1000,1.5,20,40\n", 4, "torque_nm"},
      {"-Infinity text", kHeader + kRow0 + "0.1,1000,500,100,33.3,1000,1.5,-Infinity,40\n", 3, "ambient_c"},
      {"nan time", kHeader + kRow0 + "nan,1000,500,100,33.3,1000,1.5,20,40\n", 3, "time_s"},
      {"number too large", kHeader + kRow0 + "0.1,1000,500,100,33.3,1e999,1.5,20,40\n", 3, "voltage_v"},
      {"time backwards", kHeader + kRow0 + kRow1 + "0.05,1000,500,100,33.3,1000,1.5,20,40\n", 4, "time_s"},
      {"ambient column missing",
       "time_s,speed_rpm,current_a,frequency_hz,airflow_m3s,stator_winding_c\n0,1000,100,33,1.5,40\n", 1,
       "ambient_c"},
      {"time column missing",
       "speed_rpm,current_a,frequency_hz,airflow_m3s,ambient_c,stator_winding_c\n1000,100,33,1.5,20,40\n", 1,
       "time_s"},
      {"wrong case column",
       "time_s,Speed_RPM,current_a,frequency_hz,airflow_m3s,ambient_c,stator_winding_c\n0,1000,100,33,1.5,20,40\n",
       1, "speed_rpm"},
      {"required channel entirely empty",
       kHeader + "0,1000,500,100,33.3,1000,,20,40\n0.1,1000,500,100,33.3,1000,,20,40\n", 1, "airflow_m3s"},
      {"current negative", kHeader + kRow0 + "0.1,1000,500,-5,33.3,1000,1.5,20,40\n", 3, "current_a"},
      {"speed too high", kHeader + "0,25000,500,100,33.3,1000,1.5,20,40\n", 2, "speed_rpm"},
      {"speed too low", kHeader + kRow0 + "0.1,-20000.5,500,100,33.3,1000,1.5,20,40\n", 3, "speed_rpm"},
      {"ambient too hot", kHeader + kRow0 + kRow1 + "0.2,1000,500,100,33.3,1000,1.5,80.5,40\n", 4, "ambient_c"},
      {"airflow too high", kHeader + kRow0 + "0.1,1000,500,100,33.3,1000,101,20,40\n", 3, "airflow_m3s"},
      {"winding too hot", kHeader + kRow0 + "0.1,1000,500,100,33.3,1000,1.5,20,401\n", 3, "stator_winding_c"},
      {"frequency too high", kHeader + kRow0 + "0.1,1000,500,100,-1200,1000,1.5,20,40\n", 3, "frequency_hz"},
      {"empty time cell", kHeader + kRow0 + kRow1 + ",1000,500,100,33.3,1000,1.5,20,40\n", 4, "time_s"},
      {"blank time cell", kHeader + kRow0 + "   ,1000,500,100,33.3,1000,1.5,20,40\n", 3, "time_s"},
      {"duplicate column", "time_s,speed_rpm,current_a,frequency_hz,airflow_m3s,ambient_c,stator_winding_c,speed_rpm\n",
       1, "speed_rpm"},
      {"duplicate unknown column",
       "time_s,speed_rpm,current_a,frequency_hz,airflow_m3s,ambient_c,stator_winding_c,note,note\n"
       "0,1000,100,33,1.5,20,40,a,b\n",
       1, "note"},
      {"too few cells", kHeader + kRow0 + "0.1,1000,500,100,33.3,1000,1.5,20\n", 3, ""},
      {"too many cells", kHeader + kRow0 + kRow1 + "0.2,1000,500,100,33.3,1000,1.5,20,40,7\n", 4, ""},
      {"empty file", "", 1, ""},
      {"blank file", "\n  \n", 1, ""},
      {"header only", kHeader, 1, ""},
      {"error after a blank line counts it", kHeader + kRow0 + "\n" + "0.1,1000,500,abc,33.3,1000,1.5,20,40\n", 4,
       "current_a"},
      {"CRLF keeps line numbers", "time_s,speed_rpm,current_a,frequency_hz,airflow_m3s,ambient_c,stator_winding_c\r\n"
                                  "0,1000,100,33,1.5,20,40\r\n0.1,1000,100,33,1.5,20,oops\r\n",
       3, "stator_winding_c"},
  };
}

TEST(ParseErrors, EachNamesFileLineAndColumn) {
  TempDir dir;
  for (const BadInput& bad : bad_inputs()) {
    SCOPED_TRACE(bad.what);
    const auto file = dir.write("bad_input.csv", bad.text);
    try {
      (void)load_fleet_dump({file});
      ADD_FAILURE() << "no DataError for: " << bad.what;
    } catch (const DataError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(file.string() + ":" + std::to_string(bad.line) + ": "), std::string::npos) << msg;
      if (!bad.column.empty()) {
        EXPECT_NE(msg.find("column '" + bad.column + "'"), std::string::npos) << msg;
      } else {
        EXPECT_EQ(msg.find("column '"), std::string::npos) << msg;
      }
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\r'), std::string::npos) << msg;
    }
  }
}

TEST(ParseErrors, MessageShape) {
  TempDir dir;
  const auto file = dir.write("shape.csv", kHeader + kRow0 + "0.1,1000,500,abc,33.3,1000,1.5,20,40\n");
  try {
    (void)load_cycle_file(file);
    FAIL() << "expected DataError";
  } catch (const DataError& e) {
    EXPECT_EQ(std::string(e.what()), file.string() + ":3: column 'current_a': not a number: 'abc'");
  }
}

TEST(ParseErrors, MissingPathsAndEmptyDirectories) {
  TempDir dir;
  const auto empty = dir.path() / "empty_dir";
  std::filesystem::create_directories(empty);
  dir.write("empty_dir/notes.txt", "not a csv\n");
  try {
    (void)load_fleet_dump({empty});
    FAIL() << "expected DataError";
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find(empty.string()), std::string::npos) << e.what();
  }
  const auto nowhere = dir.path() / "does_not_exist.csv";
  try {
    (void)load_fleet_dump({nowhere});
    FAIL() << "expected DataError";
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find(nowhere.string()), std::string::npos) << e.what();
  }
}

TEST(ParseErrors, TolerableInputLoads) {
  // Equal times, spaces around cells, a leading '+', exponent notation, a trailing blank line,
  // a UTF-8 BOM and quoted header names are all fine.
  TempDir dir;
  const std::string text =
      "\xEF\xBB\xBF\"time_s\", speed_rpm ,current_a,frequency_hz,airflow_m3s,ambient_c,stator_winding_c\n"
      "0, 1000 ,100,33,1.5,20,40\n"
      "0,+1000,1e2,33,1.5,20,40\n"
      " 0.1 ,1000,100,33,1.5E0,20,40\n"
      "\n";
  const auto file = dir.write("ok.csv", text);
  const Dataset d = load_fleet_dump({file});
  ASSERT_EQ(d.cycles.size(), 1u);
  EXPECT_EQ(d.cycles[0].steps, 2u);
  EXPECT_FLOAT_EQ(d.cycles[0].at(Channel::speed_rpm, 1), 1000.0f);
  EXPECT_EQ(d.reports[0].rows, 3u);
  EXPECT_EQ(d.warning_count(), 0u);
}

TEST(ParseErrors, BadOptionsAreRejected) {
  LoadOptions o;
  o.dt_s = 0;
  EXPECT_THROW((void)parse_cycle_csv(kHeader + kRow0, "x.csv", o), std::invalid_argument);
  o = {};
  o.max_gap_s[index_of(Channel::ambient_c)] = -1;
  EXPECT_THROW((void)parse_cycle_csv(kHeader + kRow0, "x.csv", o), std::invalid_argument);
}

TEST(ParseErrors, AbsurdTimeSpanIsAnError) {
  // Milliseconds written into time_s would make a grid of billions of points.
  const std::string text = kHeader + kRow0 + "1e9,1000,500,100,33.3,1000,1.5,20,40\n";
  try {
    (void)parse_cycle_csv(text, "ms.csv");
    FAIL() << "expected DataError";
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("ms.csv:3: column 'time_s'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace lptn::data
