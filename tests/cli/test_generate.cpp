// The synthetic plant's output: deterministic, realistic, loadable without warnings, and each
// hidden effect changes the truth measurably and only when switched on.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "lptn_testing/temp_dir.hpp"
#include "simulator/generate/generate.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn::cli {
namespace {

std::string read(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

gen::GenerateOptions short_options(int cycles, std::uint64_t seed, EffectSet hidden = 0) {
  gen::GenerateOptions o;
  o.cycles = cycles;
  o.seed = seed;
  o.hidden = hidden;
  o.min_duration_s = 900;
  o.max_duration_s = 1200;
  return o;
}

// Column `name` of a truth CSV as numbers.
std::vector<double> truth_column(const std::filesystem::path& file, const std::string& name) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  int col = 0, wanted = -1;
  std::stringstream header(line);
  for (std::string cell; std::getline(header, cell, ','); ++col)
    if (cell == name) wanted = col;
  EXPECT_GE(wanted, 0) << name;
  std::vector<double> out;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string cell;
    for (int c = 0; c <= wanted; ++c) std::getline(row, cell, ',');
    out.push_back(std::stod(cell));
  }
  return out;
}

TEST(Generate, SameSeedSameDataOtherSeedOtherData) {
  testing::TempDir a, b, c;
  gen::generate(short_options(2, 7), a.path());
  gen::generate(short_options(2, 7), b.path());
  gen::generate(short_options(2, 8), c.path());
  for (const char* f : {"cycle_01_suburban.csv", "cycle_02_regional.csv", "truth.json", "motor.toml"})
    EXPECT_EQ(read(a.path() / f), read(b.path() / f)) << f;
  EXPECT_NE(read(a.path() / "cycle_01_suburban.csv"), read(c.path() / "cycle_01_suburban.csv"));
}

TEST(Generate, OutputLoadsWithoutWarningsAndHasRealisticRanges) {
  testing::TempDir dir;
  gen::GenerateOptions o = short_options(5, 3);
  o.min_duration_s = o.max_duration_s = 3600;  // one kind each, an hour each
  const auto summaries = gen::generate(o, dir.path());
  const data::Dataset d = data::load_fleet_dump({dir.path()});
  EXPECT_EQ(d.warning_count(), 0u);
  ASSERT_EQ(d.cycles.size(), 5u);
  double hottest = 0;
  for (const auto& s : summaries) {
    EXPECT_GE(s.duration_s, 3599.0);
    EXPECT_LT(s.max_stator_winding_c, 200.0) << s.name;  // class 200: approached, never passed
    EXPECT_GT(s.min_ambient_c, -25.0);
    EXPECT_LT(s.max_ambient_c, 45.0);
    if (s.kind != "shunting") {
      EXPECT_GT(s.max_stator_winding_c, s.min_ambient_c + 40.0) << s.name;
    }
    hottest = std::max(hottest, s.max_stator_winding_c);
  }
  EXPECT_GT(hottest, 120.0);  // a hard cycle gets hot
  for (const data::Cycle& c : d.cycles) {
    EXPECT_TRUE(c.has(data::Channel::rotor_c));
    double max_current = 0;
    for (std::size_t k = 0; k < c.steps; ++k) max_current = std::max(max_current, double(c.at(data::Channel::current_a, k)));
    EXPECT_GT(max_current, 60.0) << c.name;
    EXPECT_LT(max_current, 2.5 * 115.0) << c.name;
  }
}

TEST(Generate, TheMeasurementsAreTheTruthPlusTheStatedNoise) {
  testing::TempDir dir;
  gen::generate(short_options(1, 5), dir.path());
  const data::Dataset d = data::load_fleet_dump({dir.path() / "cycle_01_suburban.csv"});
  const std::vector<double> truth = truth_column(dir.path() / "truth" / "cycle_01_suburban.csv", "stator_sensor_c");
  double sum_sq = 0;
  int n = 0;
  const data::Cycle& c = d.cycles[0];
  for (std::size_t k = 0; k < c.steps && k < truth.size(); k += 10) {
    // Native 1 Hz samples sit on every tenth grid point (within the time stamps' jitter).
    const float y = c.at(data::Channel::stator_winding_c, k);
    if (std::isnan(y)) continue;
    sum_sq += (y - truth[k]) * (y - truth[k]);
    ++n;
  }
  const double rms = std::sqrt(sum_sq / n);
  EXPECT_GT(rms, 0.3);
  EXPECT_LT(rms, 0.5);  // 0.4 K noise and 0.1 K quantization
}

TEST(Generate, LongGapsAreMaskedOrSplitByTheLoader) {
  testing::TempDir dir;
  gen::GenerateOptions o = short_options(1, 4);
  o.long_gaps = true;
  gen::generate(o, dir.path());
  const data::Dataset d = data::load_fleet_dump({dir.path()});
  EXPECT_GE(d.warning_count(), 2u);
  EXPECT_EQ(d.cycles.size(), 2u);  // split at the speed gap
}

class HiddenEffect : public ::testing::TestWithParam<int> {};

TEST_P(HiddenEffect, ChangesTheTruthMeasurablyAndOnlyWhenSwitchedOn) {
  const int e = GetParam();
  testing::TempDir plain, plain_again, hidden;
  auto options = [&](EffectSet h) {
    gen::GenerateOptions o = short_options(2, 11, h);
    o.min_duration_s = o.max_duration_s = 2400;  // long enough for an effect to build up
    return o;
  };
  gen::generate(options(0), plain.path());
  gen::generate(options(0), plain_again.path());
  gen::generate(options(effect_bit(e)), hidden.path());
  for (const char* cycle : {"cycle_01_suburban.csv", "cycle_02_regional.csv"}) {
    EXPECT_EQ(read(plain.path() / "truth" / cycle), read(plain_again.path() / "truth" / cycle));
    double change = 0;
    for (const char* col : {"stator_sensor_c", "rotor_winding_c", "rotor_core_c", "stator_core_c"}) {
      const auto a = truth_column(plain.path() / "truth" / cycle, col);
      const auto b = truth_column(hidden.path() / "truth" / cycle, col);
      ASSERT_EQ(a.size(), b.size());
      for (std::size_t k = 0; k < a.size(); ++k) change = std::max(change, std::abs(a[k] - b[k]));
    }
    EXPECT_GT(change, 1.0) << EffectLibrary::kNames[e] << " in " << cycle;
  }
  const auto truth = nlohmann::json::parse(read(hidden.path() / "truth.json"));
  EXPECT_EQ(truth["hidden_effects"][0], std::string(EffectLibrary::kNames[e]));
}

INSTANTIATE_TEST_SUITE_P(Library, HiddenEffect, ::testing::Range(0, kNumEffects),
                         [](const auto& param_info) { return std::string(EffectLibrary::kNames[param_info.param]); });

}  // namespace
}  // namespace lptn::cli
