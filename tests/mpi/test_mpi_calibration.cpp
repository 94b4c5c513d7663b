// `mpirun -np N lptn calibrate ...` against the same command in one process, through the CLI a
// user runs: the calibration (values and standard errors within 1e-9 relative, every metric the
// same), the fleet's factors and verdicts, the diagnosis (its LM refits shared), and a bad file
// on one rank failing the whole job.
// Open MPI runs here as the real thing (MPIEXEC, ranks oversubscribed on 2 cores).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lptn_testing/run_lptn.hpp"
#include "lptn_testing/temp_dir.hpp"

namespace lptn::calibrate {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// `lptn ARGS` under `mpirun -np RANKS` (RANKS > 1), or alone.
testing::Result lptn_on(int ranks, const std::string& args, const fs::path& scratch) {
  if (ranks == 1) return testing::run(args, scratch);
  // Open MPI refuses root unless told; CI runs as root. Ranks beyond the cores: --oversubscribe.
  setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  const std::string launcher = std::string(MPIEXEC) + " -np " + std::to_string(ranks) + " --oversubscribe ";
  const std::string cmd = launcher + LPTN_BINARY + " " + args + " >" + (scratch / "stdout.txt").string() + " 2>" +
                          (scratch / "stderr.txt").string();
  const int status = std::system(cmd.c_str());
  auto slurp = [](const fs::path& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(scratch / "stdout.txt"), slurp(scratch / "stderr.txt")};
}

json read_json(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

double relative(double a, double b) { return a == b ? 0.0 : std::abs(a - b) / std::max(std::abs(a), std::abs(b)); }

// The numbers a calibration's users read: every parameter and its error within 1e-9 relative;
// the metrics, split and data hashes identical.
void expect_same_calibration(const json& one, const json& many, int ranks) {
  ASSERT_EQ(one["parameters"].size(), many["parameters"].size());
  int calibrated = 0;
  for (std::size_t i = 0; i < one["parameters"].size(); ++i) {
    const json& a = one["parameters"][i];
    const json& b = many["parameters"][i];
    if (!a["calibrated"].get<bool>()) continue;
    ++calibrated;
    EXPECT_LE(relative(a["value"], b["value"]), 1e-9) << a["name"] << " " << a["value"] << " vs " << b["value"];
    EXPECT_LE(relative(a["std_error"], b["std_error"]), 1e-9) << a["name"];
  }
  EXPECT_GE(calibrated, 6);
  EXPECT_EQ(one["metrics"], many["metrics"]);
  EXPECT_EQ(one["data"], many["data"]);  // files, hashes and the split
  EXPECT_EQ(one["method"]["details"]["iterations"], many["method"]["details"]["iterations"]);
  EXPECT_EQ(one["method"]["details"]["residuals"], many["method"]["details"]["residuals"]);
  EXPECT_EQ(one["method"]["details"]["mpi_ranks"], 1);
  EXPECT_EQ(many["method"]["details"]["mpi_ranks"], ranks);
  const auto shares = many["method"]["details"]["rank_residuals"].get<std::vector<std::size_t>>();
  ASSERT_EQ(shares.size(), static_cast<std::size_t>(ranks));
  std::size_t sum = 0;
  for (std::size_t n : shares) sum += n;
  EXPECT_EQ(sum, one["method"]["details"]["residuals"].get<std::size_t>());
}

// The training work spread evenly: no rank idles in the sums while another simulates. Within one
// cycle's worth of residuals of each other (the balance moves whole cycles).
void expect_balanced(const json& calibration, std::size_t largest_cycle) {
  const auto shares = calibration["method"]["details"]["rank_residuals"].get<std::vector<std::size_t>>();
  const auto [low, high] = std::minmax_element(shares.begin(), shares.end());
  EXPECT_LE(*high - *low, largest_cycle) << calibration["method"]["details"]["rank_residuals"];
}

TEST(MpiCalibration, EqualsOneProcessOnEveryRankCount) {
  testing::TempDir dir;
  // Seven cycles of 20-30 minutes, some files cut in pieces by long gaps (a file of several
  // cycles must stay whole on one rank): 3 ranks take 3, 2 and 2 files.
  ASSERT_EQ(testing::run("generate --out " + (dir.path() / "dump").string() +
                             " --cycles 7 --minutes-min 20 --minutes-max 30 --long-gaps --seed 5",
                         dir.path()).code, 0);
  const std::string common = "calibrate --data " + (dir.path() / "dump").string() + " --motor " +
                             (dir.path() / "dump" / "motor.toml").string() + " --quiet --out ";
  ASSERT_EQ(lptn_on(1, common + (dir.path() / "one.json").string(), dir.path()).code, 0);
  const json one = read_json(dir.path() / "one.json");
  ASSERT_GT(one["data"]["files"].size(), 7u) << "the long gaps should have cut some files into several cycles";
  for (int ranks : {2, 3}) {
    const fs::path out = dir.path() / ("ranks" + std::to_string(ranks) + ".json");
    const testing::Result r = lptn_on(ranks, common + out.string(), dir.path());
    ASSERT_EQ(r.code, 0) << r.err;
    SCOPED_TRACE(std::to_string(ranks) + " ranks");
    const json many = read_json(out);
    expect_same_calibration(one, many, ranks);
    // 30 minutes at 10 Hz, two sensors: no cycle has more residuals.
    expect_balanced(many, 2 * 30 * 600);
  }
}

// A plant with an eddy-current loss the paper's model lacks: one process and two warn alike that
// the model is not adequate on the stator sensor, with the same noise, although balancing moves
// cycles between the ranks without their files' loader reports (which hold the sensors' rates).
TEST(MpiCalibration, AnInadequateModelIsWarnedAsByOneProcess) {
  testing::TempDir dir;
  ASSERT_EQ(testing::run("generate --out " + (dir.path() / "dump").string() +
                             " --cycles 8 --minutes-min 20 --minutes-max 25 --plant eddy_loss --seed 3",
                         dir.path()).code, 0);
  const std::string common = "calibrate --data " + (dir.path() / "dump").string() + " --motor " +
                             (dir.path() / "dump" / "motor.toml").string() + " --quiet --out ";
  const testing::Result alone = lptn_on(1, common + (dir.path() / "one.json").string(), dir.path());
  ASSERT_EQ(alone.code, 3) << alone.err;
  const testing::Result two = lptn_on(2, common + (dir.path() / "two.json").string(), dir.path());
  ASSERT_EQ(two.code, 3) << two.err;
  const json one = read_json(dir.path() / "one.json"), many = read_json(dir.path() / "two.json");
  EXPECT_EQ(one["metrics"], many["metrics"]);
  // "... test RMSE 1.644 K = 4.1x its noise of 0.400 K ...": the same words up to where the
  // residual is largest, which only one process can say.
  const auto inadequate = [](const json& calibration) {
    std::vector<std::string> out;
    for (const json& w : calibration["warnings"])
      if (w["code"] == "not_adequate") {
        const std::string m = w["message"].get<std::string>();
        out.push_back(m.substr(0, m.find(" (estimated from its readings)")));
      }
    return out;
  };
  ASSERT_EQ(inadequate(one).size(), 1u) << one["warnings"];
  EXPECT_EQ(inadequate(one), inadequate(many));
  EXPECT_EQ(inadequate(one)[0].rfind("the model is not adequate on the stator sensor: ", 0), 0u) << inadequate(one)[0];
}

TEST(MpiCalibration, AFleetSharedByMotorsEqualsOneProcess) {
  testing::TempDir dir;
  ASSERT_EQ(testing::run("generate --fleet --motors 5 --cycles 1 --minutes-min 30 --minutes-max 40 --seed 7 --out " +
                             (dir.path() / "fleet").string(),
                         dir.path()).code, 0);
  const std::string common = "calibrate --fleet " + (dir.path() / "fleet").string() + " --motor " +
                             (dir.path() / "fleet" / "motor.toml").string() + " --quiet --out ";
  // Written (0, or 3 with warnings: five short drives pin the type less well), and the same outcome on 2 ranks.
  const int alone = lptn_on(1, common + (dir.path() / "one.json").string(), dir.path()).code;
  ASSERT_TRUE(alone == 0 || alone == 3) << alone;
  const testing::Result r = lptn_on(2, common + (dir.path() / "two.json").string(), dir.path());
  ASSERT_EQ(r.code, alone) << r.err;
  const json one = read_json(dir.path() / "one.json"), two = read_json(dir.path() / "two.json");
  expect_same_calibration(one["pooled"], two["pooled"], 2);
  ASSERT_EQ(one["motors"].size(), 5u);
  int outliers = 0;
  for (const auto& [id, a] : one["motors"].items()) {
    const json& b = two["motors"][id];
    EXPECT_LE(relative(a["cooling_factor"], b["cooling_factor"]), 1e-9) << id;
    EXPECT_LE(relative(a["cooling_factor_std"], b["cooling_factor_std"]), 1e-9) << id;
    EXPECT_EQ(a["outlier"], b["outlier"]) << id;
    EXPECT_EQ(a["metrics"], b["metrics"]) << id;
    outliers += a["outlier"].get<bool>();
  }
  EXPECT_EQ(outliers, 1) << "the weak motor, named in both runs";
}

// Every number of a JSON document against another's within `tolerance` relative (timings aside),
// every string and flag equal. Returns how many numbers were compared.
int expect_same_numbers(const json& a, const json& b, const std::string& path, double tolerance) {
  if (path.find("seconds") != std::string::npos) return 0;
  if (a.is_object()) {
    int n = 0;
    EXPECT_EQ(a.size(), b.size()) << path;
    for (const auto& [key, value] : a.items())
      if (b.contains(key)) n += expect_same_numbers(value, b[key], path + "/" + key, tolerance);
    return n;
  }
  if (a.is_array()) {
    int n = 0;
    EXPECT_EQ(a.size(), b.size()) << path;
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i)
      n += expect_same_numbers(a[i], b[i], path + "[" + std::to_string(i) + "]", tolerance);
    return n;
  }
  if (a.is_number_float()) {
    EXPECT_LE(relative(a.get<double>(), b.get<double>()), tolerance) << path;
    return 1;
  }
  EXPECT_EQ(a, b) << path;
  return 0;
}

TEST(MpiCalibration, DiagnoseSharesItsRefitsAndSaysTheSame) {
  testing::TempDir dir;
  const std::string dump = (dir.path() / "dump").string();
  ASSERT_EQ(testing::run("generate --out " + dump + " --cycles 6 --minutes-min 20 --minutes-max 30 --hidden windage --seed 3",
                         dir.path()).code, 0);
  const std::string calibration = (dir.path() / "c.json").string();
  // The paper's model with windage hidden: written, with warnings or without.
  const int calibrated = testing::run("calibrate --quiet --data " + dump + " --motor " + dump + "/motor.toml --out " + calibration,
                                      dir.path()).code;
  ASSERT_TRUE(calibrated == 0 || calibrated == 3) << calibrated;
  const std::string diagnose = "diagnose --quiet --data " + dump + " --calibration " + calibration + " --json-out ";
  const testing::Result one = lptn_on(1, diagnose + (dir.path() / "one.json").string(), dir.path());
  ASSERT_EQ(one.code, 0) << one.err;
  const testing::Result two = lptn_on(2, diagnose + (dir.path() / "two.json").string(), dir.path());
  ASSERT_EQ(two.code, 0) << two.err;
  EXPECT_EQ(one.out, two.out) << "the verdict a user reads, printed once";
  EXPECT_NE(one.out.find("windage"), std::string::npos) << one.out;
  const int numbers = expect_same_numbers(read_json(dir.path() / "one.json"), read_json(dir.path() / "two.json"), "", 1e-9);
  EXPECT_GT(numbers, 100);
}

TEST(MpiCalibration, ABadFileOnOneRankFailsTheJobAndWritesNothing) {
  testing::TempDir dir;
  ASSERT_EQ(testing::run("generate --out " + (dir.path() / "dump").string() +
                             " --cycles 3 --minutes-min 5 --minutes-max 6 --seed 2",
                         dir.path()).code, 0);
  // The second file (rank 1's) gets a cell that is not a number on its line 5.
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir.path() / "dump"))
    if (e.path().extension() == ".csv") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  ASSERT_EQ(files.size(), 3u);
  std::ifstream in(files[1]);
  std::string text((std::istreambuf_iterator<char>(in)), {}), line;
  std::size_t at = 0;
  for (int i = 0; i < 4; ++i) at = text.find('\n', at) + 1;
  text.replace(at, text.find(',', at) - at, "twelve");
  std::ofstream(files[1]) << text;
  const fs::path out = dir.path() / "c.json";
  const testing::Result r = lptn_on(2,
                                    "calibrate --data " + (dir.path() / "dump").string() + " --motor " +
                                        (dir.path() / "dump" / "motor.toml").string() + " --quiet --out " + out.string(),
                                    dir.path());
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find(files[1].filename().string() + ":5:"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(MpiCalibration, Td3UnderMpirunIsRefusedNotRunOnEveryRank) {
  testing::TempDir dir;
  ASSERT_EQ(testing::run("generate --out " + (dir.path() / "dump").string() + " --cycles 2 --minutes-min 5 --minutes-max 6",
                         dir.path()).code, 0);
  const fs::path out = dir.path() / "c.json";
  const testing::Result r = lptn_on(2,
                                    "calibrate --method td3 --data " + (dir.path() / "dump").string() + " --motor " +
                                        (dir.path() / "dump" / "motor.toml").string() + " --out " + out.string(),
                                    dir.path());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("not shared over MPI"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace lptn::calibrate
