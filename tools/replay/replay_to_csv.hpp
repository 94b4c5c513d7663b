// A CAN log (candump, Vector ASC or BLF) through the estimator into a CSV of estimates (written
// atomically), with a progress line and malformed records reported (the first ten, then a count):
// what `lptn replay` and `lptn vcan-bench` run.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "lptn/firmware/estimator_config.hpp"
#include "firmware/linux/input_tally.hpp"
#include "firmware/linux/replay.hpp"
#include "can/canfile/can_log.hpp"
#include "trainer/data/inspection.hpp"

namespace lptn::replay {

// How often a node's reported spread covers its telemetry: the share of ticks with a fresh reading
// where |estimate - reading| <= 2 sqrt(sigma^2 + noise^2). sigma is the estimate's spread about the
// TRUE temperature; the reading is the truth plus the sensor's noise, independent of the estimate,
// so the difference spreads by both (2 sigma alone would call an exact estimate wrong whenever the
// sensor's noise exceeds it). The noise is the telemetry's own, from the log: second differences of
// its readings 2 s apart (y0 - 2 y1 + y2 has variance 6 noise^2; 2 s is beyond the sender's or a
// converter's holding or interpolating between its samples, and a linear trend cancels).
struct BandCoverage {
  std::size_t ticks = 0, within = 0;
  double sensor_noise_k = 0;
  double share() const { return ticks ? static_cast<double>(within) / static_cast<double>(ticks) : 0.0; }
};

struct ReplaySummary {
  fw::ReplayStats stats;
  fw::InputTally inputs;  // how each input reached the model (fw::input_warnings says it)
  // The estimates against the readings on the bus: the stator winding's (which the filter fuses,
  // so this is near its noise) and the rotor telemetry's (never fused: a check of an unmeasured node).
  double rmse_stator_k = 0, rmse_rotor_k = 0;
  std::size_t stator_samples = 0, rotor_samples = 0;
  BandCoverage stator_coverage, rotor_coverage;  // of the stator winding's and the rotor winding's spread
  // The cooling factor's estimate at the log's end, and when the cooling alarm first rose (s from
  // the log's start; negative: never).
  double cooling_factor = 1, cooling_factor_std = 0;
  fw::CoolingState cooling_state = fw::CoolingState::off;
  double cooling_alarm_from_s = -1;
  double seconds = 0;  // wall time of the replay (reading, estimating, writing)
  canfile::LogFormat format = canfile::LogFormat::candump;  // what the log was read as
};


// `select`: the log's format (none: detected) and channel ("": all; frames of several channels are
// read as one bus, with a warning). `inputs_check`, where given, gets at every row the values the
// log last sent for speed, current, frequency and voltage, plausible or not (NaN: none yet): the
// check of the log against the motor's nameplate, which the model's own inputs cannot serve
// (conditioning keeps values outside the nameplate's plausible ranges from them). Throws
// std::invalid_argument (bad input: a log that cannot be read, is in no format lptn reads, holds
// no frame, or none on the channel asked for) or std::runtime_error (the output could not be
// written); nothing is left at `csv` then.
ReplaySummary replay_to_csv(const std::string& log, const fw::EstimatorConfig<double>& config, const std::string& csv,
                              bool quiet, const canfile::LogSelection& select = {},
                              data::NameplateCheck* inputs_check = nullptr);

}  // namespace lptn::replay
