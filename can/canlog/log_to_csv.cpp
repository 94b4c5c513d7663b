// CAN log (candump, ASC, BLF) -> fleet-dump CSV.

#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "can/canlog/bus_channels.hpp"
#include "can/canlog/convert.hpp"
#include "can/canlog/internal/open_for_conversion.hpp"
#include "can/canfile/can_log.hpp"

namespace lptn::canlog {
namespace {

namespace fs = std::filesystem;
using data::Channel;
using data::kNumChannels;
using Values = std::array<double, kNumChannels>;  // NaN: no cell

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();


// Frames that are well formed but carry no column.
enum class Skip { unknown_id, output_frame, error_frame, remote_frame, fd_frame, wrong_length, unmapped_page };
constexpr std::array<const char*, 7> kSkipNames{"unknown id",   "estimator output (LPTN_*)", "error frame",
                                                "remote frame", "CAN FD",                    "wrong length",
                                                "multiplexor value with no mapped signal"};

// The columns an input frame carries (NaN elsewhere), or why it carries none.
struct Decoded {
  std::optional<Skip> skip;
  Values values;
};

Decoded decode(const fw::CanFrame& f) {
  Decoded d{std::nullopt, {}};
  d.values.fill(kNaN);
  if (f.error) return {Skip::error_frame, d.values};
  if (f.remote) return {Skip::remote_frame, d.values};
  if (f.fd) return {Skip::fd_frame, d.values};
  if (is_output_frame(f.id, f.extended)) return {Skip::output_frame, d.values};
  d.skip = Skip::unknown_id;
  for_each_input_message([&](const auto& m) {
    using Msg = typename std::decay_t<decltype(m)>::Frame;
    if (f.id != Msg::kId || f.extended != Msg::kExtended) return;
    Msg msg;
    if (f.len != Msg::kLength || !msg.unpack(f.data, f.len)) {
      d.skip = Skip::wrong_length;
      return;
    }
    d.skip.reset();
    for (const auto& s : m.signals) d.values[data::index_of(s.channel)] = s.decode(msg);
  });
  return d;
}

// The decimals that print every value of a signal exactly: 0.05 -> 2, 0.0005 -> 4, 0.5 -> 1.
int decimals_of(double factor) {
  int d = 0;
  for (double scaled = factor; d < 9 && std::fabs(scaled - std::round(scaled)) > 1e-9 * scaled; scaled *= 10) ++d;
  return d;
}

std::array<int, kNumChannels> column_decimals() {
  std::array<int, kNumChannels> decimals{};
  for_each_input_message([&](const auto& m) {
    for (const auto& s : m.signals) decimals[data::index_of(s.channel)] = decimals_of(s.factor);
  });
  return decimals;
}

// "TC_Cooling (0x120)" for the message that carries column c.
std::string message_of(Channel c) {
  std::string name;
  for_each_input_message([&](const auto& m) {
    using Msg = typename std::decay_t<decltype(m)>::Frame;
    for (const auto& s : m.signals) {
      if (s.channel != c) continue;
      char id[16];
      std::snprintf(id, sizeof id, " (0x%03X)", static_cast<unsigned>(Msg::kId));
      name = Msg::kName + std::string(id);
    }
  });
  return name;
}

// The same three for a bus map read at run time (lptn convert --bus).
class MappedColumns {
 public:
  explicit MappedColumns(const lptn::bus::BusMap& map) : map_(map), decoder_(map.decoder()) {
    for (const lptn::bus::MappedMessage& m : map.messages())
      for (const lptn::bus::MappedInput& in : m.inputs) {
        const std::optional<Channel> c = data::channel_from_name(in.column);
        if (!c) throw std::logic_error("bus vocabulary column is no fleet-dump column: " + in.column);
        channel_[fw::index_of(in.input)] = *c;
      }
  }

  Decoded decode(const fw::CanFrame& f) const {
    Decoded d{std::nullopt, {}};
    d.values.fill(kNaN);
    if (f.error) return {Skip::error_frame, d.values};
    if (f.remote) return {Skip::remote_frame, d.values};
    fw::BusReading r;
    if (!decoder_.decode(decoder_.context, f, r))
      return {is_output_frame(f.id, f.extended) ? Skip::output_frame : Skip::unknown_id, d.values};
    if (r.malformed) return {f.fd ? Skip::fd_frame : Skip::wrong_length, d.values};
    if (r.n == 0) return {Skip::unmapped_page, d.values};
    for (int k = 0; k < r.n; ++k) d.values[data::index_of(channel_[fw::index_of(r.input[k])])] = r.value[k];
    return d;
  }

  std::array<int, kNumChannels> decimals() const {
    std::array<int, kNumChannels> out{};
    for (const lptn::bus::MappedMessage& m : map_.messages())
      for (const lptn::bus::MappedInput& in : m.inputs)
        out[data::index_of(channel_[fw::index_of(in.input)])] = decimals_of(std::fabs(in.signal->factor * in.scale));
    return out;
  }

  std::string message_of(Channel c) const {
    for (const lptn::bus::MappedMessage& m : map_.messages())
      for (const lptn::bus::MappedInput& in : m.inputs) {
        if (channel_[fw::index_of(in.input)] != c) continue;
        char id[16];
        std::snprintf(id, sizeof id, " (0x%03X)", static_cast<unsigned>(m.message->id));
        return m.message->name + id;
      }
    return "a message of " + map_.file().string() + " (it maps no signal to " + std::string(data::channel_name(c)) + ")";
  }

 private:
  const lptn::bus::BusMap& map_;
  fw::BusDecoder decoder_;
  Channel channel_[fw::kNumInputs]{};
};

struct Row {
  TimeUs t;
  Values values;
};

// Collects rows and what was left out, then writes the CSV with the columns that occurred.
class CsvBuilder {
 public:
  CsvBuilder(const fs::path& log, const frames::FrameSource& source, const lptn::bus::BusMap* map)
      : log_(log), source_(source) {
    if (map) mapped_.emplace(*map);
  }

  void frame(TimeUs t, const fw::CanFrame& f, std::size_t number) {
    const Decoded d = mapped_ ? mapped_->decode(f) : decode(f);
    if (d.skip) return count_skip(*d.skip, number);
    if (!rows_.empty() && t < last_us_) {
      char reason[128];
      std::snprintf(reason, sizeof reason, "time stamp %.6f s goes back %.6f s behind the frame before; dropped",
                    static_cast<double>(t) / fw::kUsPerS, static_cast<double>(last_us_ - t) / fw::kUsPerS);
      return record_warning(number, reason);
    }
    take(t, d.values);
  }

  void bad(std::size_t number, const char* reason) { record_warning(number, reason); }

  Converted finish() {
    if (rows_.empty())
      throw ConvertError(log_.string() + ": no frame of an input message could be read (lines dropped: " +
                         std::to_string(bad_lines_) + (skipped_total() ? "; skipped: " + skipped_summary() : "") + ")");
    require_contract_columns();
    Converted out;
    out.frames = frames_;
    out.duration_s = static_cast<double>(rows_.back().t - rows_.front().t) / fw::kUsPerS;
    out.warnings = std::move(warnings_);
    if (bad_lines_ > canfile::kRecordMessagesShown)
      out.warnings.push_back(log_.string() + ": " + std::to_string(bad_lines_ - canfile::kRecordMessagesShown) +
                             " more " + source_.record_name() + "s dropped (malformed or going back in time)");
    if (skipped_total() > 0)
      out.warnings.push_back(log_.string() + ": skipped frames that carry no column: " + skipped_summary());
    out.text = csv_text();
    return out;
  }

 private:
  // "FILE:LINE: reason", or "FILE: object N: reason" for a BLF; after the first few, only counted
  // (a garbage file should not bury the terminal).
  void record_warning(std::size_t number, const char* reason) {
    if (++bad_lines_ > canfile::kRecordMessagesShown) return;
    warnings_.push_back(canfile::record_message(log_, source_, number, reason));
  }

  void count_skip(Skip why, std::size_t number) {
    const auto i = static_cast<std::size_t>(why);
    if (skipped_[i]++ == 0) first_skipped_line_[i] = number;
  }

  // A frame at the last row's time fills that row unless it would overwrite one of its cells.
  void take(TimeUs t, const Values& v) {
    bool new_row = rows_.empty() || rows_.back().t != t;
    for (int i = 0; i < kNumChannels && !new_row; ++i) new_row = !std::isnan(v[i]) && !std::isnan(rows_.back().values[i]);
    if (new_row) {
      rows_.push_back({t, {}});
      rows_.back().values.fill(kNaN);
    }
    for (int i = 0; i < kNumChannels; ++i) {
      if (std::isnan(v[i])) continue;
      rows_.back().values[i] = v[i];
      present_[i] = true;
    }
    last_us_ = t;
    ++frames_;
  }

  std::size_t skipped_total() const {
    std::size_t n = 0;
    for (std::size_t k : skipped_) n += k;
    return n;
  }

  // "3 unknown id (first on line 7), 1 remote frame (first on line 9)"
  std::string skipped_summary() const {
    std::string s;
    for (std::size_t i = 0; i < skipped_.size(); ++i) {
      if (skipped_[i] == 0) continue;
      s += (s.empty() ? "" : ", ") + std::to_string(skipped_[i]) + " " + kSkipNames[i] + " (first on line " +
           std::to_string(first_skipped_line_[i]) + ")";
    }
    return s;
  }

  void require_contract_columns() const {
    std::string missing_messages, missing_columns;
    for (Channel c : data::kAllChannels) {
      if (!data::channel_info(c).required || present_[data::index_of(c)]) continue;
      const std::string message = mapped_ ? mapped_->message_of(c) : message_of(c);
      if (missing_messages.find(message) == std::string::npos)
        missing_messages += (missing_messages.empty() ? "" : ", ") + message;
      missing_columns += (missing_columns.empty() ? "" : ", ") + std::string(data::channel_name(c));
    }
    if (!missing_messages.empty())
      throw ConvertError(log_.string() + ": no frame of " + missing_messages +
                         " in the log; the fleet-dump contract requires " + missing_columns);
  }

  // "%lld.%06lld" of seconds and microseconds (snprintf per row was a tenth of a conversion).
  static std::size_t time_text(char* buf, std::size_t size, TimeUs t) {
    if (t < 0)
      return static_cast<std::size_t>(std::snprintf(buf, size, "%lld.%06lld", static_cast<long long>(t / fw::kUsPerS),
                                                    static_cast<long long>(t % fw::kUsPerS)));
    char* p = std::to_chars(buf, buf + size, static_cast<long long>(t / fw::kUsPerS)).ptr;
    *p++ = '.';
    long long us = static_cast<long long>(t % fw::kUsPerS);
    for (int i = 5; i >= 0; --i, us /= 10) p[i] = static_cast<char>('0' + us % 10);
    return static_cast<std::size_t>(p + 6 - buf);
  }

  std::string csv_text() const {
    const std::array<int, kNumChannels> decimals = mapped_ ? mapped_->decimals() : column_decimals();
    std::string s(data::kTimeColumn);
    for (Channel c : data::kAllChannels)
      if (present_[data::index_of(c)]) s.append(",").append(data::channel_name(c));
    s += '\n';
    char buf[64];
    for (const Row& r : rows_) {
      const TimeUs t = r.t - rows_.front().t;  // exact: the log's microseconds, no rounding
      s.append(buf, time_text(buf, sizeof buf, t));
      for (int i = 0; i < kNumChannels; ++i) {
        if (!present_[i]) continue;
        s += ',';
        if (std::isnan(r.values[i])) continue;  // missing stays an empty cell, as in the contract
        s.append(buf, std::to_chars(buf, buf + sizeof buf, r.values[i], std::chars_format::fixed, decimals[i]).ptr);
      }
      s += '\n';
    }
    return s;
  }

  const fs::path& log_;
  const frames::FrameSource& source_;
  std::optional<MappedColumns> mapped_;
  std::vector<Row> rows_;
  std::array<bool, kNumChannels> present_{};
  TimeUs last_us_ = 0;
  std::size_t frames_ = 0, bad_lines_ = 0;
  std::array<std::size_t, kSkipNames.size()> skipped_{}, first_skipped_line_{};
  std::vector<std::string> warnings_;
};

}  // namespace

Converted csv_from_log(const fs::path& log, const canfile::LogSelection& select, const lptn::bus::BusMap* map) {
  const canfile::OpenedLog opened = internal::open_for_conversion(log, select);
  canfile::ChannelFilter& source = *opened.frames;
  CsvBuilder builder(log, source, map);
  TimeUs t = 0;
  fw::CanFrame frame;
  const char* why = nullptr;
  for (frames::FrameSource::Status s; (s = source.next(t, frame, why)) != frames::FrameSource::Status::end;) {
    if (s == frames::FrameSource::Status::bad) builder.bad(source.record(), why);
    else builder.frame(t, frame, source.record());
  }
  bool fatal = false;
  const std::string channels = canfile::channel_problem(log, source, select, fatal);
  if (fatal) throw ConvertError(channels);
  Converted out = builder.finish();
  if (!channels.empty()) out.warnings.push_back(channels);
  return out;
}

}  // namespace lptn::canlog
