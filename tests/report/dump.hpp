// The generated dump the report's browser tests read: windage hidden in the data, so that the
// paper's model (cal/1-paper.json, the report's calibration) fits the stator to its noise and
// misses the rotor, as in the README's loop; cal/2-windage.json adds windage, for a History whose
// rotor error falls. Made once per ctest run by lptn_report_make_dump (a ctest fixture: under the
// sanitizers generating and calibrating take a minute and a half), or by the suite itself when it
// runs by hand.
#pragma once

#include <filesystem>
#include <string>

#include "lptn_testing/run_lptn.hpp"

namespace lptn::testing {

// "" when made, else what failed. Read-only for the tests: each writes into a directory of its own.
inline std::string make_report_dump(const std::filesystem::path& d) {
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d / "cal");
  const auto gen = run("generate --out " + (d / "data").string() +
                           " --cycles 3 --seed 3 --minutes-min 15 --minutes-max 20 --hidden windage", d);
  if (gen.code != 0) return "generate: " + gen.err;
  const std::string calibrate = "calibrate --quiet --data " + (d / "data").string() + " --motor " +
                                (d / "data" / "motor.toml").string() + " --method lm";
  const auto cal = run(calibrate + " --out " + (d / "cal" / "1-paper.json").string(), d);
  // The paper's model on 35 minutes of data with windage hidden: its fit ends with a rotor
  // conductance on its bound, not converged (status failed, exit 4), and the report must show
  // that calibration all the same: it is the one that fails.
  if (cal.code != 0 && cal.code != 3 && cal.code != 4) return "calibrate: " + cal.err;
  const auto cal2 = run(calibrate + " --effect windage --out " + (d / "cal" / "2-windage.json").string(), d);
  if (cal2.code != 0 && cal2.code != 3) return "calibrate --effect windage: " + cal2.err;
  return "";
}

}  // namespace lptn::testing
