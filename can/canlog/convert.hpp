// Fleet-dump CSV <-> CAN log (candump -L, what canplayer plays; Vector ASC or BLF), through the
// DBC's generated codecs: the data a calibration was fitted on, played onto a bus as the converter would send it,
// and a recorded bus turned into data the trainer loads.
#pragma once

#include <cstddef>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "hostio/bad_input.hpp"
#include "lptn/firmware/input.hpp"
#include "can/bus/bus_map.hpp"
#include "can/canfile/can_log.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn::canlog {

// Bad input: one line naming the file (and line, column and signal where there are such).
class ConvertError : public hostio::BadInput {
 public:
  using BadInput::BadInput;
};

struct Converted {
  std::string text;  // the whole output file (BLF: its bytes)
  std::size_t frames = 0;  // written (CSV -> log) or taken (log -> CSV)
  double duration_s = 0;  // first to last frame
  std::vector<std::string> warnings;  // one line each, naming the file (and line where there is one)
};

struct LogOptions {
  canfile::LogFormat format = canfile::LogFormat::candump;
  std::string interface = "can0";  // candump's; ASC and BLF write channel 1
  fw::TimeUs start_us = 0;  // time stamp of the first grid point the loader kept
  // The converter's frames (bus.toml, read at run time); none: our own TC_* frames, through the
  // codecs generated from lptn.dbc.
  const lptn::bus::BusMap* bus = nullptr;
  // How the CSV is read (its data map); by default as every command reads it.
  data::LoadOptions load;
};

// CSV -> log. The CSV is loaded as every command loads it (resampled onto the 0.1 s grid, gaps
// bridged, masked or split by the loader's rules). Every input message goes out every cycle time
// at a fixed phase after its grid point, carrying the grid values there, wherever all of its
// columns have one; each message's alive counter counts the frames of it actually sent.
// Throws data::DataError for a CSV the loader refuses, ConvertError for a value outside its DBC
// signal's range. With a bus map, each message goes out every cycle time the map or its DBC gives
// (a whole number of grid steps), a multiplexed one as one frame per multiplexor value its mapped
// signals need; signals the map does not name are sent as raw 0, inputs it leaves out not at all.
Converted log_from_csv(const std::filesystem::path& csv, const LogOptions& options);

// log -> CSV. One row per frame time (frames with the same time stamp share a row), time_s counted
// from the first frame taken, a cell per column the frame carries. Malformed lines and frames whose
// time stamp goes backwards are warned about and dropped; frames that carry no column (unknown ids,
// the estimator's outputs, error, remote, CAN FD, wrong length) are counted in one summary warning.
// Columns whose message never appeared are left out. Throws ConvertError if the log cannot be
// opened, no frame could be taken or a required column's message never appeared.
// `select`: the log's format (none: detected) and channel ("": all, with a warning where there are
// several; none on the channel asked for is an error).
// `bus`: the converter's frames (bus.toml); none: our own TC_* frames.
Converted csv_from_log(const std::filesystem::path& log, const canfile::LogSelection& select,
                       const lptn::bus::BusMap* bus = nullptr);

// log -> log in format `to`: every frame as it was (id, flags, data, time stamp), nothing decoded.
// Records that are no frame and frames stamped before the frame before them are dropped, each
// kind counted in one warning. Throws ConvertError if the log cannot be opened or holds no frame.
// `interface`: candump's interface name on every line.
Converted log_from_log(const std::filesystem::path& log, const canfile::LogSelection& select, canfile::LogFormat to,
                       const std::string& interface = "can0");

}  // namespace lptn::canlog
