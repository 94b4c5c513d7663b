// A CAN log (candump, Vector ASC or BLF) through the estimator into a CSV of estimates (written
// atomically), with a progress line and malformed records reported (the first ten, then a count):
// what `lptn replay` and `lptn vcan-bench` run.
#pragma once

#include <optional>
#include <string>

#include "lptn/firmware/estimator_config.hpp"
#include "firmware/linux/replay.hpp"
#include "tools/canfile/can_log.hpp"

namespace lptn {

struct ReplaySummary {
  fw::ReplayStats stats;
  // The estimates against the readings on the bus: the stator winding's (which the filter fuses,
  // so this is near its noise) and the rotor telemetry's (never fused: a check of an unmeasured node).
  double rmse_stator_k = 0, rmse_rotor_k = 0;
  std::size_t stator_samples = 0, rotor_samples = 0;
  // The cooling factor's estimate at the log's end, and when the cooling alarm first rose (s from
  // the log's start; negative: never).
  double cooling_factor = 1, cooling_factor_std = 0;
  fw::CoolingState cooling_state = fw::CoolingState::off;
  double cooling_alarm_from_s = -1;
  double seconds = 0;  // wall time of the replay (reading, estimating, writing)
  canfile::LogFormat format = canfile::LogFormat::candump;  // what the log was read as
};

// `select`: the log's format (none: detected) and channel ("": all; frames of several channels are
// read as one bus, with a warning). Throws std::invalid_argument (bad input: a log that cannot be
// read, is in no format lptn reads, holds no frame, or none on the channel asked for) or
// std::runtime_error (the output could not be written); nothing is left at `csv` then.
ReplaySummary replay_to_csv(const std::string& log, const fw::EstimatorConfig<double>& config, const std::string& csv,
                              bool quiet, const canfile::LogSelection& select = {});

}  // namespace lptn
