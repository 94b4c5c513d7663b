// lptn convert: a fleet-dump CSV as a CAN log (candump -L, what canplayer plays onto a bus; Vector
// ASC or BLF, what CANoe and CANalyzer replay), and such a log back into the fleet-dump CSV contract.
#include <algorithm>
#include <atomic>
#include <exception>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "can/canfile/can_log.hpp"
#include "can/canlog/bus_channels.hpp"
#include "can/canlog/convert.hpp"
#include "programs/cli/bus_option.hpp"
#include "programs/cli/data_map_option.hpp"
#include "programs/cli/blas_threads.hpp"
#include "programs/cli/commands.hpp"
#include "hostio/atomic_file.hpp"
#include "hostio/worker_threads.hpp"

namespace lptn::cli {
namespace {

namespace fs = std::filesystem;

struct ConvertArgs {
  std::string in, out, interface = "can0", format, channel, bus, data_map_path;
  double start_time_s = 0;
  bool force = false;
  std::shared_ptr<const bus::BusMap> map;  // --bus, read once for every file of a directory
  data::LoadOptions load;  // --map, read once likewise
};

// The message table as the help shows it, so that the help cannot disagree with the code.
std::string messages_help() {
  std::string s;
  canlog::for_each_input_message([&](const auto& m) {
    using Msg = typename std::decay_t<decltype(m)>::Frame;
    char head[96];
    std::snprintf(head, sizeof head, "  %-16s 0x%03X every %4u ms at +%u ms:", Msg::kName,
                  static_cast<unsigned>(Msg::kId), static_cast<unsigned>(Msg::kCycleTimeMs),
                  static_cast<unsigned>(m.phase_us / 1000));
    s += head;
    for (const auto& sig : m.signals) s.append(" ").append(data::channel_name(sig.channel));
    s += '\n';
  });
  return s;
}

std::string footer() {
  return "Direction: an input *.csv becomes a log; a log (*.log candump -L, *.asc Vector ASC, *.blf\n"
         "Vector BLF, *.mf4 MDF4 bus logging) becomes a CSV, or, with --out named as a log (x.log, x.asc, x.blf, x.mf4), that\n"
         "log in the other format, every frame as it was; a file named otherwise is a log with --format or if its content is one\n"
         "(BLF's \"LOGG\", MDF4's identification block, a candump line, an ASC header among its first lines), else a CSV. A\n"
         "directory converts every *.csv in it into OUT/NAME.log (.asc, .blf, .mf4 with --format), or every\n"
         "log into OUT/NAME.csv (not both kinds at once).\n"
         "\n"
         "Formats: --format, else the extension of --out (CSV -> log) or the log's content (log -> CSV).\n"
         "candump lines carry --interface; ASC, BLF and MDF4 carry channel 1, every frame received (Rx), time\n"
         "stamps counted from the first frame, whose time starts the file (ASC's date, BLF's and MDF4's header).\n"
         "\n"
         "CSV -> log: the CSV is loaded as every lptn command loads it (0.1 s grid, the loader's gap\n"
         "rules). Each input message of can/codecs/lptn.dbc goes out every cycle time, shortly after its\n"
         "grid point, with the grid values there:\n" +
         messages_help() +
         "A message is not sent where one of its columns has no value (never, if the column is absent).\n"
         "Each message's AliveCounter counts its frames; PulsesEnabled is current_a > 0.5 A. Time stamps\n"
         "are --start-time plus the time since the first grid point, in whole microseconds: the same CSV\n"
         "gives the same bytes. A value outside its signal's DBC range is an error (exit 2, nothing\n"
         "written).\n"
         "\n"
         "log -> CSV: one row per frame time, time_s counted from the first input frame, each frame\n"
         "filling the columns it carries; --channel takes one bus of a log that holds several (without\n"
         "it they are read as one, with a warning). Malformed lines (BLF:\n"
         "objects; MDF4: records and blocks, by byte offset) and frames going back in time are reported (FILE:LINE, the first ten, then a count)\n"
         "and dropped; unknown ids, LPTN_* outputs, error, remote, CAN FD and wrong-length\n"
         "frames are skipped and counted. Columns whose message never appears are left out; the ones the\n"
         "contract requires must appear.\n"
         "\n"
         "--bus bus.toml: the converter's own frames instead of ours, as its map names them\n"
         "(docs/onboard.md, \"Your converter's bus\"): each mapped message every cycle time, 1 ms apart\n"
         "within a grid step, a multiplexed one as a frame per multiplexor value, each with its alive\n"
         "counter; signals the map does not name are sent as 0.\n";
}

std::string lower_extension(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

std::optional<canfile::LogFormat> given_format(const ConvertArgs& args) {
  if (args.format.empty()) return std::nullopt;
  return canfile::format_from_name(args.format);
}

// A log or a CSV: by the name where it says, else by --format, else by the content (a log's, or a CSV).
bool is_log(const fs::path& file, const ConvertArgs& args) {
  const std::string ext = lower_extension(file);
  if (ext == ".csv") return false;
  if (canfile::format_from_extension(file) || given_format(args)) return true;
  try {
    canfile::detect_format(file);
    return true;
  } catch (const canfile::LogError&) {
    return false;
  }
}

// CSV -> log: --format, else the extension of the log to write, else candump.
canfile::LogFormat output_format(const ConvertArgs& args, const fs::path& out) {
  return given_format(args).value_or(canfile::format_from_extension(out).value_or(canfile::LogFormat::candump));
}

// Bad input throws the readers' own kinds (canlog::ConvertError, canfile::LogError): BadInput.
canlog::Converted convert(const fs::path& in, const fs::path& out, bool from_log, const ConvertArgs& args) {
  // A log to a log's name: the frames again in that format (never a CSV under a log's name).
  if (from_log && canfile::format_from_extension(out))
    return canlog::log_from_log(in, {std::nullopt, args.channel}, *canfile::format_from_extension(out), args.interface);
  if (from_log) return canlog::csv_from_log(in, {given_format(args), args.channel}, args.map.get());
  canlog::LogOptions options;
  options.format = output_format(args, out);
  options.interface = args.interface;
  options.start_us = std::llround(args.start_time_s * 1e6);
  options.bus = args.map.get();
  options.load = args.load;
  return canlog::log_from_csv(in, options);
}

void print_warnings(const canlog::Converted& c) {
  for (const std::string& w : c.warnings) std::fprintf(stderr, "lptn: warning: %s\n", w.c_str());
}

// --interface and --start-time shape the log; on the way back they would silently do nothing.
void reject_log_options(const CLI::App& cmd, const fs::path& in) {
  if (cmd.count("--interface") || cmd.count("--start-time"))
    throw hostio::BadInput("--interface and --start-time apply to CSV -> log only; " + in.string() + " converts log -> CSV");
}

// --channel picks frames of a log; a CSV has none.
void reject_channel(const CLI::App& cmd, const fs::path& in) {
  if (cmd.count("--channel")) throw hostio::BadInput("--channel applies to log -> CSV only; " + in.string() + " converts CSV -> log");
}

// Only candump lines name an interface.
void reject_interface(const CLI::App& cmd, canfile::LogFormat format) {
  if (cmd.count("--interface") && format != canfile::LogFormat::candump)
    throw hostio::BadInput(std::string("--interface applies to candump logs; ") + canfile::format_name(format) +
                   " logs carry channel 1");
}

void convert_file(const CLI::App& cmd, const ConvertArgs& args) {
  const fs::path in(args.in), out(args.out);
  if (fs::exists(out) && fs::equivalent(in, out)) throw hostio::BadInput(args.out + ": is the input");
  if (fs::is_directory(out)) throw hostio::BadInput(args.out + ": is a directory (one input file makes one output file)");
  check_output_path(args.out, args.force);
  const bool from_log = is_log(in, args);
  const auto out_log = canfile::format_from_extension(out);
  if (from_log && out_log) {
    if (cmd.count("--start-time")) throw hostio::BadInput("--start-time applies to CSV -> log only; a log keeps its own time stamps");
    if (cmd.count("--format")) throw hostio::BadInput("--format: log -> log takes the input's format from its content and the output's from " + args.out);
    reject_interface(cmd, *out_log);
  } else if (from_log) {
    reject_log_options(cmd, in);
  } else {
    reject_channel(cmd, in);
    reject_interface(cmd, output_format(args, out));
  }
  const canlog::Converted c = convert(in, out, from_log, args);
  print_warnings(c);
  hostio::write_file_atomically(out, c.text);
  std::printf("wrote %s (%zu frames, %.2f h)\n", args.out.c_str(), c.frames, c.duration_s / 3600);
}

// The *.csv and the log files (*.log, *.asc, *.blf, *.mf4) directly in `dir`, each sorted by name.
void list_inputs(const fs::path& dir, std::vector<fs::path>& csvs, std::vector<fs::path>& logs) {
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    if (lower_extension(e.path()) == ".csv") csvs.push_back(e.path());
    if (canfile::format_from_extension(e.path())) logs.push_back(e.path());
  }
  std::sort(csvs.begin(), csvs.end());
  std::sort(logs.begin(), logs.end());
}

void convert_directory(const CLI::App& cmd, const ConvertArgs& args) {
  const fs::path in(args.in);
  std::vector<fs::path> csvs, logs;
  list_inputs(in, csvs, logs);
  if (!csvs.empty() && !logs.empty())
    throw hostio::BadInput(args.in + ": holds both *.csv and log files; convert one kind at a time");
  if (csvs.empty() && logs.empty()) throw hostio::BadInput(args.in + ": no *.csv, *.log, *.asc, *.blf or *.mf4 files in this directory");
  if (fs::exists(args.out) && fs::equivalent(in, args.out)) throw hostio::BadInput(args.out + ": is the input directory");
  check_output_path(args.out, args.force);
  const bool from_log = !logs.empty();
  const canfile::LogFormat log_format = given_format(args).value_or(canfile::LogFormat::candump);
  if (from_log) {
    reject_log_options(cmd, in);
  } else {
    reject_channel(cmd, in);
    reject_interface(cmd, log_format);
  }
  const std::vector<fs::path>& files = from_log ? logs : csvs;
  const std::string out_ext = from_log ? ".csv" : canfile::format_extension(log_format);

  // The files are converted over the cores (each file on one thread, the next to whichever is
  // free), each output written as it is done; reported in the order of the names, as one at a time
  // would: a bad file (the first by name) ends it after the ones before it, and nothing is written.
  hostio::AtomicDirectory out(args.out, args.force);
  struct Item {
    std::size_t frames = 0;
    double duration_s = 0;
    std::vector<std::string> warnings;
    std::exception_ptr failure;
  };
  std::vector<Item> items(files.size());
  std::atomic<std::size_t> next{0};
  const int threads = hostio::worker_threads();
  hostio::parallel_for(static_cast<std::size_t>(threads), threads, [&](std::size_t) {
    for (std::size_t i; (i = next.fetch_add(1)) < files.size();) {
      Item& item = items[i];
      try {
        const std::string name = files[i].stem().string() + out_ext;
        canlog::Converted c = convert(files[i], name, from_log, args);
        hostio::write_file_atomically(out.path() / name, c.text);
        item.frames = c.frames;
        item.duration_s = c.duration_s;
        item.warnings = std::move(c.warnings);
      } catch (...) {
        item.failure = std::current_exception();
      }
    }
  });
  std::size_t frames = 0;
  double hours = 0;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const Item& item = items[i];
    if (item.failure) std::rethrow_exception(item.failure);
    for (const std::string& w : item.warnings) std::fprintf(stderr, "lptn: warning: %s\n", w.c_str());
    const std::string name = files[i].stem().string() + out_ext;
    frames += item.frames;
    hours += item.duration_s / 3600;
    std::fprintf(stderr, "[%zu/%zu] %s -> %s: %zu frames, %.2f h\n", i + 1, files.size(),
                 files[i].filename().string().c_str(), name.c_str(), item.frames, item.duration_s / 3600);
  }
  out.commit();
  std::printf("wrote %zu %s (%zu frames, %.1f h) to %s\n", files.size(), from_log ? "CSVs" : "logs", frames, hours,
              args.out.c_str());
}

// What canplayer and the candump log format take as an interface name.
std::string check_interface(const std::string& name) {
  const bool ok = !name.empty() && name.size() < 16 && std::all_of(name.begin(), name.end(), [](unsigned char c) {
    return std::isalnum(c) || c == '_' || c == '-' || c == '.';
  });
  return ok ? "" : "an interface name is 1 to 15 letters, digits, '_', '-' or '.'";
}

}  // namespace

void add_convert(CLI::App& app) {
  auto* cmd = app.add_subcommand("convert", "Convert a fleet-dump CSV into a CAN log (candump, Vector ASC, BLF or MDF4; "
                                            "through the DBC's encoders), or such a log into a fleet-dump CSV");
  auto args = std::make_shared<ConvertArgs>();
  cmd->add_option("--in", args->in, "A cycle CSV, a CAN log (candump -L, Vector ASC, BLF or MDF4), or a directory of either")
      ->required()
      ->check(CLI::ExistingPath);
  cmd->add_option("--out", args->out, "The log or CSV to write; a directory if --in is one")->required();
  cmd->add_option("--format", args->format, "The log's format: candump, asc, blf or mdf4 (default: by extension or content)")
      ->check(CLI::IsMember({"candump", "asc", "blf", "mdf4"}));
  cmd->add_option("--channel", args->channel,
                  "log -> CSV: only the frames of this channel (candump: an interface name; ASC, BLF, MDF4: a number)");
  cmd->add_option("--interface", args->interface, "CSV -> candump log: interface name on every line")
      ->capture_default_str()
      ->check(CLI::Validator(check_interface, "NAME"));
  cmd->add_option("--start-time", args->start_time_s, "CSV -> log: time stamp of the first frame, s (e.g. epoch seconds)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 9999999999.0));
  cmd->add_option("--bus", args->bus,
                  "Bus map (bus.toml): the converter DBC's messages and signals for each column (default: our own "
                  "TC_* frames of lptn.dbc)");
  add_map_option(cmd, args->data_map_path);
  cmd->add_flag("--force", args->force, "Replace --out if it exists");
  cmd->footer(footer());
  cmd->callback([cmd, args] {
    stop_blas_threads();
    if (!args->bus.empty()) check_input_path(args->bus, "--bus", InputPath::file);
    if (!args->bus.empty()) args->map = read_bus_map(args->bus);
    args->load = with_map(args->data_map_path);
    if (fs::is_directory(args->in)) {
      convert_directory(*cmd, *args);
    } else {
      convert_file(*cmd, *args);
    }
  });
}

}  // namespace lptn::cli
