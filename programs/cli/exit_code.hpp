// A command's outcome beyond success (0) and bad input (2), for scripts and fleet pipelines:
//   1  lptn check: the calibration does not hold on this data
//   3  lptn calibrate: written, with warnings (calibration.json "status": "warnings")
//   4  lptn calibrate: written for inspection only, the fit failed ("status": "failed")
// A command sets it as it finishes; run_cli returns it once the command returned normally.
#pragma once

namespace lptn::cli {

inline constexpr int kExitDoesNotHold = 1;
inline constexpr int kExitWarnings = 3;
inline constexpr int kExitFailed = 4;

void set_exit_code(int code);
int exit_code();

}  // namespace lptn::cli
