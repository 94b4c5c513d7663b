#pragma once
// What `lptn inspect` prints about a loaded fleet dump, and plausibility checks against the motor.

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lptn/nameplate.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn::data {

// Per file: duration, rows, each channel's native rate, samples and coverage, the gaps, the
// findings, the segments it became; then "N cycles, H h of data, W warnings".
std::string format_report(const Dataset& dataset);

// Same content. Keys: cycles[].{name, file, duration_s, rows, channels{NAME: {present,
// native_rate_hz, samples, coverage, gaps[{start_s, end_s, line_before, line_after, action}]}},
// findings[{severity, message}], segments[{name, start_s, duration_s, steps}]}, cycle_count,
// hours, warnings.
nlohmann::json report_json(const Dataset& dataset);

// The motor's nameplate (lptn/nameplate.hpp); the checks below read its pole pairs, rated current
// and rated voltage.
using Nameplate = lptn::Nameplate<double>;

// Warnings, one per cycle and check, when the data does not look like this motor: current above
// 4x rated, voltage above 1.3x rated, or stator frequency more than 10 Hz away from
// speed * pole_pairs / 60 for more than 1% of the time both are present.
// Throws std::invalid_argument when pole_pairs, rated current or rated voltage is not positive.
std::vector<Finding> check_against_nameplate(const Dataset& dataset, const Nameplate& nameplate);

// check_against_nameplate() of one cycle, sample by sample: for a caller whose samples come one at
// a time (lptn replay, tick by tick) rather than as a loaded cycle. A sample is what the cycle
// would hold at a step (float; NaN: absent).
class NameplateCheck {
 public:
  explicit NameplateCheck(const Nameplate& nameplate);  // throws as check_against_nameplate()
  void add(float speed_rpm, float current_a, float frequency_hz, float voltage_v);
  // `who` opens each finding's message: "cycle NAME (FILE)".
  std::vector<Finding> findings(const std::string& who) const;

 private:
  struct Over {  // samples of one channel above its limit
    std::size_t valid = 0, over = 0;
    double peak = -HUGE_VAL;
    void add(float v, double limit);
  };
  Nameplate nameplate_;
  Over current_, voltage_;
  std::size_t both_ = 0, off_ = 0;  // steps with speed and frequency; of those, the frequency off
};

// Every warning `lptn inspect` finds in this dump, one line each (each names its file), for the
// commands that read a dump to repeat before their results: what the loader tolerated (unknown or
// misnamed columns, ignored; gaps it could not bridge; segments dropped) and, with the motor's
// nameplate, check_against_nameplate's (another pole count, a channel's scaling). The loader's
// "info" findings (an optional column absent) are not warnings and are left out.
std::vector<std::string> inspection_warnings(const Dataset& dataset);
std::vector<std::string> inspection_warnings(const Dataset& dataset, const Nameplate& nameplate);

}  // namespace lptn::data
