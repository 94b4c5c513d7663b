// A generated fleet dump for the tests: written by the generator into a temporary directory and
// loaded, with a split (the LM, coarse-grid, search and TD3 suites; the diagnose tests' dumps,
// calibrated, are small_fleet.hpp's).
#pragma once

#include <cstdint>

#include "lptn_testing/temp_dir.hpp"
#include "simulator/generate/generate.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::testing {

// A dump on disk and loaded: its directory (removed with it), cycles, motor file and split.
struct Dump {
  TempDir dir;
  data::Dataset dataset;
  MotorFile motor;
  calibrate::Split split;
};

// `options`' dump written into d.dir and loaded (d.split left for the caller).
inline void write_and_load(Dump& d, const gen::GenerateOptions& options) {
  gen::generate(options, d.dir.path());
  d.dataset = data::load_fleet_dump({d.dir.path()});
  d.motor = load_motor_file(d.dir.path() / "motor.toml");
}

// `cycles` cycles of `min_s`..`max_s` seconds from `seed`, nothing hidden; `test_fraction` of them
// held out (the split's own seed 1).
inline void generate_dump(Dump& d, int cycles, std::uint64_t seed, double min_s, double max_s, double test_fraction) {
  gen::GenerateOptions o;
  o.cycles = cycles;
  o.seed = seed;
  o.min_duration_s = min_s;
  o.max_duration_s = max_s;
  write_and_load(d, o);
  d.split = calibrate::split_cycles(d.dataset, {}, test_fraction, 1);
}

}  // namespace lptn::testing
