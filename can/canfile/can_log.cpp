#include "can/canfile/can_log.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>

#include "lptn/firmware/candump_line.hpp"
#include "hostio/line_reader.hpp"
#include "can/canfile/internal/formats.hpp"

namespace lptn::canfile {

namespace fs = std::filesystem;

const char* format_name(LogFormat f) {
  switch (f) {
    case LogFormat::candump: return "candump";
    case LogFormat::asc: return "asc";
    case LogFormat::blf: return "blf";
    case LogFormat::mdf4: return "mdf4";
  }
  return "?";
}

std::optional<LogFormat> format_from_name(std::string_view name) {
  for (LogFormat f : {LogFormat::candump, LogFormat::asc, LogFormat::blf, LogFormat::mdf4})
    if (name == format_name(f)) return f;
  return std::nullopt;
}

const char* format_extension(LogFormat f) {
  switch (f) {
    case LogFormat::candump: return ".log";
    case LogFormat::asc: return ".asc";
    case LogFormat::blf: return ".blf";
    case LogFormat::mdf4: return ".mf4";
  }
  return "";
}

std::optional<LogFormat> format_from_extension(const fs::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (LogFormat f : {LogFormat::candump, LogFormat::asc, LogFormat::blf, LogFormat::mdf4})
    if (ext == format_extension(f)) return f;
  return std::nullopt;
}

std::string record_message(const fs::path& file, const frames::FrameSource& source, std::size_t record,
                           std::string_view reason) {
  const std::string_view name = source.record_name();
  if (name == "record") return file.string() + ": " + std::string(reason);  // MDF4: the reason names the byte offset
  return file.string() + (name == "line" ? ":" : ": object ") + std::to_string(record) + ": " + std::string(reason);
}

namespace {

File open_file(const fs::path& file) {
  File f(std::fopen(file.c_str(), "rb"), &std::fclose);
  if (!f) throw LogError(file.string() + ": cannot open for reading");
  return f;
}

// How many non-empty lines the content test reads before it gives up.
constexpr int kLinesToSniff = 10;

std::optional<LogFormat> format_from_content(const fs::path& file) {
  File f = open_file(file);
  char magic[4] = {};
  char mdf[8] = {};
  if (std::fread(magic, 1, 4, f.get()) == 4 && std::memcmp(magic, kBlfMagic, 4) == 0) return LogFormat::blf;
  std::rewind(f.get());
  if (std::fread(mdf, 1, 8, f.get()) == 8 &&
      (std::memcmp(mdf, kMdfMagic, 8) == 0 || std::memcmp(mdf, kMdfUnfinishedMagic, 8) == 0))
    return LogFormat::mdf4;
  std::rewind(f.get());
  hostio::LineReader reader(f.get());
  std::string_view line;
  int seen = 0;
  for (hostio::LineReader::Status s; seen < kLinesToSniff && (s = reader.next(line)) != hostio::LineReader::Status::end;) {
    if (s == hostio::LineReader::Status::too_long) {
      ++seen;
      continue;
    }
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.front()))) line.remove_prefix(1);
    if (line.empty()) continue;
    ++seen;
    fw::CandumpRecord rec;
    if (fw::parse_candump_line(line, rec) == nullptr) return LogFormat::candump;
    if (is_asc_header_line(line)) return LogFormat::asc;
  }
  return std::nullopt;
}

}  // namespace

LogFormat detect_format(const fs::path& file) {
  if (const auto f = format_from_content(file)) return *f;
  if (const auto f = format_from_extension(file)) return *f;
  throw LogError(file.string() +
                 ": not a CAN log lptn reads (candump -L, Vector ASC, Vector BLF or MDF4; --format names one)");
}

std::unique_ptr<frames::FrameSource> open_log(const fs::path& file, LogFormat format) {
  switch (format) {
    case LogFormat::candump: return make_candump_source(open_file(file));
    case LogFormat::asc: return make_asc_source(open_file(file));
    case LogFormat::blf: return make_blf_source(open_file(file), file);
    case LogFormat::mdf4: return make_mdf4_source(open_file(file), file);
  }
  throw LogError(file.string() + ": unknown log format");
}

std::unique_ptr<frames::FrameSource> open_log(std::FILE* stream, LogFormat format, const std::string& name) {
  File file(stream, &std::fclose);
  switch (format) {
    case LogFormat::candump: return make_candump_source(std::move(file));
    case LogFormat::asc: return make_asc_source(std::move(file));
    case LogFormat::blf: return make_blf_source(std::move(file), name);
    case LogFormat::mdf4: return make_mdf4_source(std::move(file), name);
  }
  throw LogError(name + ": unknown log format");
}

frames::FrameSource::Status ChannelFilter::next(fw::TimeUs& time_us, fw::CanFrame& frame, const char*& why) {
  for (;;) {
    const Status s = source_->next(time_us, frame, why);
    if (s != Status::frame) return s;
    const std::string_view channel = source_->channel();
    if (std::find(channels_.begin(), channels_.end(), channel) == channels_.end()) channels_.emplace_back(channel);
    if (wanted_.empty() || channel == wanted_) return s;
  }
}

std::string ChannelFilter::channel_list() const {
  std::string s;
  for (const std::string& c : channels_) s += (s.empty() ? "" : ", ") + c;
  return s;
}

OpenedLog open_log(const fs::path& file, const LogSelection& selection) {
  const LogFormat format = selection.format ? *selection.format : detect_format(file);
  return {format, std::make_unique<ChannelFilter>(open_log(file, format), selection.channel)};
}

std::string channel_problem(const fs::path& file, const ChannelFilter& frames, const LogSelection& selection,
                            bool& fatal) {
  const auto& seen = frames.channels();
  fatal = !selection.channel.empty() && std::find(seen.begin(), seen.end(), selection.channel) == seen.end();
  if (fatal)
    return file.string() + ": no frame on channel " + selection.channel +
           (seen.empty() ? std::string(" (no frame at all)") : " (the log's channels: " + frames.channel_list() + ")");
  if (selection.channel.empty() && seen.size() > 1)
    return file.string() + ": frames of channels " + frames.channel_list() +
           " read as one bus; --channel picks one";
  return "";
}

std::unique_ptr<LogWriter> make_log_writer(LogFormat format, const std::string& interface) {
  switch (format) {
    case LogFormat::candump: return make_candump_writer(interface);
    case LogFormat::asc: return make_asc_writer();
    case LogFormat::blf: return make_blf_writer();
    case LogFormat::mdf4: return make_mdf4_writer();
  }
  throw LogError("unknown log format");
}

}  // namespace lptn::canfile
