// Vector ASC, the text log of CANoe and CANalyzer (and python-can's ASCWriter):
//   date Tue Nov 24 06:30:55.123 am 2026
//   base hex  timestamps absolute
//   Begin Triggerblock Tue Nov 24 06:30:55.123 am 2026
//      0.012345 1  101             Rx   d 8 0A 1B 2C 3D 00 00 00 05  Length = 0 BitCount = 0 ID = 257
//      0.013000 1  18FEF100x       Rx   d 3 01 02 03
//      0.014000 1  200             Rx   r 8
//      0.015000 1  ErrorFrame
//      0.016000 CANFD   1 Rx      101  Name  1 0 f 64 00 01 ... 0 0 1000 0 0 0 0 0
//   End TriggerBlock
// Time stamps count from the measurement's start (each from the one before with "timestamps
// relative"); ids and data are hexadecimal, or decimal with "base dec". Lines of other events
// (statistics, system variables, "Start of measurement") carry no frame and are passed over.
#include <array>
#include <cctype>
#include <cstdint>
#include <ctime>
#include <string>

#include "can/canfile/internal/block_line_reader.hpp"
#include "can/canfile/internal/formats.hpp"
#include "lptn/firmware/hex_digit.hpp"

namespace lptn::canfile {
namespace {

using fw::CanFrame;
using frames::FrameSource;
using fw::TimeUs;

// ASC's field separators: blank, tab and a Windows line's '\r'. One load a byte, where three
// comparisons were three branches.
struct Separators {
  bool is[256];
  constexpr Separators() : is() { is[' '] = is['\t'] = is['\r'] = true; }
};
inline constexpr Separators kSeparators{};
inline bool is_separator(char c) { return kSeparators.is[static_cast<unsigned char>(c)]; }

// Whitespace-separated fields of one line; more than kMax are not looked at. Only the first n
// are set: an array of string_views would be zeroed whole for every line (1.5 KB, a tenth of an
// ASC replay's parsing).
struct Fields {
  static constexpr std::size_t kMax = 96;
  struct Span {
    const char* data;
    std::size_t size;
  };
  Span f[kMax];
  std::size_t n = 0;
  explicit Fields(std::string_view line) {
    const char* p = line.data();
    const char* const end = p + line.size();
    while (n < kMax) {
      while (p != end && is_separator(*p)) ++p;
      if (p == end) break;
      const char* const start = p;
      while (p != end && !is_separator(*p)) ++p;
      f[n++] = {start, static_cast<std::size_t>(p - start)};
    }
  }
  std::string_view operator[](std::size_t k) const { return k < n ? std::string_view(f[k].data, f[k].size) : std::string_view{}; }
};

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
  return true;
}

bool istarts_with(std::string_view s, std::string_view prefix) {
  return s.size() >= prefix.size() && iequals(s.substr(0, prefix.size()), prefix);
}

// Digits of `base` (16 or 10) from p: the byte after them, their value in `value` (wrapping past
// 64 bits, which max_digits rules out); nullptr for none or more than max_digits.
const char* read_digits(const char* p, const char* end, int base, int max_digits, std::uint64_t& value) {
  const char* const start = p;
  value = 0;
  for (; p != end; ++p) {
    const int d = fw::hex_value(*p);
    if (d < 0 || d >= base) break;
    value = value * static_cast<unsigned>(base) + static_cast<unsigned>(d);
  }
  const std::ptrdiff_t count = p - start;
  return count > 0 && count <= max_digits ? p : nullptr;
}

// A time stamp from p, "12.345678": 1 to 12 digits of seconds, then optionally a point and any
// number of decimals (the first six microseconds, the seventh rounding). The byte after it, or
// nullptr if p starts no such number.
const char* read_seconds(const char* p, const char* end, TimeUs& t) {
  std::uint64_t sec;
  if ((p = read_digits(p, end, 10, 12, sec)) == nullptr) return nullptr;
  TimeUs us = 0;
  bool round_up = false;
  if (p != end && *p == '.') {
    ++p;
    int i = 0;
    for (; p != end; ++p, ++i) {
      const unsigned d = static_cast<unsigned char>(*p) - unsigned{'0'};
      if (d > 9) break;
      if (i < 6) us = us * 10 + d;
      else if (i == 6) round_up = d >= 5;
    }
    for (; i < 6; ++i) us *= 10;
  }
  t = static_cast<TimeUs>(sec) * fw::kUsPerS + us + (round_up ? 1 : 0);
  return p;
}

// A field that is a time stamp, in microseconds, rounded; false if it is no such number.
// (An absent field is an empty view whose data() may be null, as read_*'s nullptr: ruled out first.)
bool seconds_us(std::string_view s, TimeUs& out) {
  const char* const end = s.data() + s.size();
  return !s.empty() && read_seconds(s.data(), end, out) == end;
}

// A field that is an id, a length code or a data byte in `base`: at most 10 digits and `max`.
bool number(std::string_view s, int base, std::uint32_t max, std::uint32_t& out) {
  const char* const end = s.data() + s.size();
  std::uint64_t v;
  if (s.empty() || read_digits(s.data(), end, base, 10, v) != end || v > max) return false;
  out = static_cast<std::uint32_t>(v);
  return true;
}

// "101" or "18FEF100x" (extended).
const char* parse_id(std::string_view s, int base, CanFrame& f) {
  f.extended = !s.empty() && (s.back() == 'x' || s.back() == 'X');
  if (f.extended) s.remove_suffix(1);
  if (!number(s, base, f.extended ? 0x1FFFFFFFu : 0x7FFu, f.id))
    return f.extended ? "extended id is not a number below 0x20000000" : "id is not a number of 11 bits (an 'x' marks an extended id)";
  return nullptr;
}

// No log spans more (seconds_us reads at most 12 digits of seconds, about 31,700 years).
constexpr TimeUs kMaxTimeUs = TimeUs{100} * 366 * 86400 * fw::kUsPerS;

bool is_direction(std::string_view s) { return s == "Rx" || s == "Tx"; }

const char* parse_data(const Fields& fields, std::size_t first, std::size_t count, int base, CanFrame& f) {
  if (fields.n < first + count) return "fewer data bytes than its length says";
  for (std::size_t i = 0; i < count; ++i) {
    std::uint32_t b;
    if (!number(fields[first + i], base, 0xFF, b)) return "a data byte is not a number from 0 to 255";
    f.data[i] = static_cast<std::uint8_t>(b);
  }
  f.len = static_cast<std::uint8_t>(count);
  return nullptr;
}

// Classic CAN, from the field after the channel: ID DIR d|r DLC DATA...
const char* parse_classic(const Fields& fields, int base, CanFrame& f) {
  if (const char* why = parse_id(fields[2], base, f)) return why;
  const std::string_view kind = fields[4];
  std::uint32_t dlc = 0;
  if (kind == "r" || kind == "R") {
    f.remote = true;
    if (fields.n > 5 && number(fields[5], 16, 15, dlc)) f.len = static_cast<std::uint8_t>(dlc > 8 ? 8 : dlc);
    return nullptr;
  }
  if (kind != "d" && kind != "D") return "expected 'd' (data) or 'r' (remote) after the direction";
  if (!number(fields[5], 16, 15, dlc)) return "data length code is not a hex digit";
  return parse_data(fields, 6, dlc > 8 ? 8 : dlc, base, f);
}

// CAN FD, from the field after "CANFD": CH DIR ID [NAME] BRS ESI DLC LENGTH DATA...
const char* parse_fd(const Fields& fields, int base, CanFrame& f) {
  if (fields[4] == "ErrorFrame") {
    f.error = true;
    return nullptr;
  }
  if (const char* why = parse_id(fields[4], base, f)) return why;
  // A symbolic name is an identifier; BRS is a digit.
  const std::size_t brs = fields[5].size() == 1 && std::isdigit(static_cast<unsigned char>(fields[5][0])) ? 5 : 6;
  std::uint32_t dlc = 0, length = 0;
  if (!number(fields[brs + 2], 16, 15, dlc)) return "CAN FD data length code is not a hex digit";
  if (!number(fields[brs + 3], 10, 64, length)) return "CAN FD data length is not a number from 0 to 64";
  f.fd = true;
  if (length == 0 && kFdLengths[dlc] != 0) {  // no data with a length code: a remote frame
    f.remote = true;
    f.len = kFdLengths[dlc];
    return nullptr;
  }
  return parse_data(fields, brs + 4, length, base, f);
}

// The line nearly every log is made of, a classic data frame on a numbered channel,
//     0.012345 1  101             Rx   d 8 0A 1B 2C 3D 00 00 00 05 ...
// read in one pass over its bytes: where the fields are found first, finding them was half of
// an ASC replay's parsing. False for any other line, and for anything in this one the general
// reading (Fields, parse_classic) would not take as it stands; that reading then has the line,
// so that every line gets what the general reading gives it (the same frame, or its complaint).
class ClassicLine {
 public:
  explicit ClassicLine(std::string_view line) : p_(line.data()), end_(line.data() + line.size()) {}

  bool read(int base, TimeUs& t, std::string_view& channel, CanFrame& frame) {
    // Each field read as its bytes are passed, not found first and read again: the time stamp,
    // the channel, the id, the direction and 'd' as the general reading takes them.
    if (!seconds_here(t)) return false;
    skip_separators();
    const char* const channel_start = p_;
    std::uint64_t value = 0;
    if (!digits_here(10, 10, value) || value > 0xFFFF) return false;
    channel = std::string_view(channel_start, static_cast<std::size_t>(p_ - channel_start));
    // Into the caller's frame: a line this reading gives up on leaves it changed, which no reader
    // of a FrameSource looks at after anything but a frame (a frame made here and copied was a
    // tenth of this reading).
    CanFrame& f = frame;
    f = CanFrame{};
    skip_separators();
    if (!digits_here(base, 10, value, true)) return false;
    f.extended = p_ != end_ && (*p_ == 'x' || *p_ == 'X');
    if (f.extended) ++p_;
    if (!at_field_end() || value > (f.extended ? 0x1FFFFFFFu : 0x7FFu)) return false;
    f.id = static_cast<std::uint32_t>(value);
    skip_separators();
    if (end_ - p_ < 2 || (p_[0] != 'R' && p_[0] != 'T') || p_[1] != 'x') return false;
    p_ += 2;
    if (!at_field_end()) return false;
    skip_separators();
    if (p_ == end_ || (*p_ != 'd' && *p_ != 'D')) return false;
    ++p_;
    if (!at_field_end()) return false;
    std::string_view field;
    std::uint32_t dlc;
    if (!next_field(field) || !number(field, 16, 15, dlc)) return false;
    f.len = static_cast<std::uint8_t>(dlc > 8 ? 8 : dlc);
    std::uint32_t byte;
    for (std::uint8_t i = 0; i < f.len; ++i) {
      // A blank, two hex digits and the field's end: a data byte as logs write it.
      if (base == 16 && end_ - p_ >= 3 && p_[0] == ' ') {
        const int hi = fw::hex_value(p_[1]), lo = fw::hex_value(p_[2]);
        if (hi >= 0 && lo >= 0 && (end_ - p_ == 3 || is_separator(p_[3]))) {
          f.data[i] = static_cast<std::uint8_t>(hi << 4 | lo);
          p_ += 3;
          continue;
        }
      }
      if (!next_field(field) || !number(field, base, 0xFF, byte)) return false;
      f.data[i] = static_cast<std::uint8_t>(byte);
    }
    return true;
  }

 private:
  void skip_separators() {
    while (p_ != end_ && is_separator(*p_)) ++p_;
  }
  // The field that starts at p_ (false at the line's end).
  bool field_here(std::string_view& field) {
    if (p_ == end_) return false;
    const char* const start = p_;
    while (p_ != end_ && !is_separator(*p_)) ++p_;
    field = std::string_view(start, static_cast<std::size_t>(p_ - start));
    return true;
  }
  bool next_field(std::string_view& field) {
    skip_separators();
    return field_here(field);
  }
  bool at_field_end() const { return p_ == end_ || is_separator(*p_); }
  // read_digits() from p_, then the field's end, or with `suffix_may_follow` anything (the caller
  // looks at what follows).
  bool digits_here(int base, int max_digits, std::uint64_t& value, bool suffix_may_follow = false) {
    const char* const after = read_digits(p_, end_, base, max_digits, value);
    if (after == nullptr) return false;
    p_ = after;
    return suffix_may_follow || at_field_end();
  }
  // The time stamp field, as seconds_us() reads it.
  bool seconds_here(TimeUs& t) {
    skip_separators();
    const char* const after = read_seconds(p_, end_, t);
    if (after == nullptr) return false;
    p_ = after;
    return at_field_end();
  }

  const char* p_;
  const char* const end_;
};

class AscSource final : public FrameSource {
 public:
  explicit AscSource(File file) : file_(std::move(file)), reader_(file_.get()) {}

  Status next(TimeUs& time_us, CanFrame& frame, const char*& why) override {
    std::string_view line;
    for (BlockLineReader::Status s; (s = reader_.next(line)) != BlockLineReader::Status::end;) {
      if (s == BlockLineReader::Status::too_long) {
        why = "line longer than 512 bytes, not an ASC line";
        return Status::bad;
      }
      TimeUs t;
      std::string_view classic_channel;
      if (ClassicLine(line).read(base_, t, classic_channel, frame) && !(relative_ && t > kMaxTimeUs - last_us_)) {
        if (relative_) t += last_us_;
        last_us_ = t;
        channel_ = classic_channel;
        time_us = t;
        return Status::frame;
      }
      const Fields fields(line);
      if (fields.n == 0) continue;
      if (!seconds_us(fields[0], t)) {
        if (header(line, fields)) continue;
        why = "expected a time stamp (seconds) at the start of an ASC event line";
        return Status::bad;
      }
      if (relative_) {
        if (t > kMaxTimeUs - last_us_) {
          why = "relative time stamps add up to more than a century";
          return Status::bad;
        }
        t += last_us_;
      }
      last_us_ = t;
      const bool fd = fields[1] == "CANFD";
      std::uint32_t channel;
      if (!fd && !number(fields[1], 10, 0xFFFF, channel)) continue;  // an event on no CAN channel
      CanFrame f;
      if (fd) {
        if (!is_direction(fields[3])) continue;  // TxRq and the like: not on the bus
        why = parse_fd(fields, base_, f);
      } else if (fields[2] == "ErrorFrame") {
        f.error = true;
        why = nullptr;
      } else if (is_direction(fields[3])) {
        why = parse_classic(fields, base_, f);
      } else {
        continue;  // statistics, chip status, a transmit request, ...
      }
      if (why) return Status::bad;
      channel_ = fd ? fields[2] : fields[1];
      time_us = t;
      frame = f;
      return Status::frame;
    }
    return Status::end;
  }
  std::size_t record() const override { return reader_.line_number(); }
  const char* record_name() const override { return "line"; }
  std::string_view channel() const override { return channel_; }

 private:
  // The header's lines; "base" sets how ids and data and time stamps are read.
  bool header(std::string_view line, const Fields& fields) {
    if (iequals(fields[0], "base")) {
      base_ = iequals(fields[1], "dec") ? 10 : 16;
      relative_ = fields.n > 3 && iequals(fields[3], "relative");
      return true;
    }
    return is_asc_header_line(line);
  }

  File file_;
  BlockLineReader reader_;
  int base_ = 16;
  bool relative_ = false;
  std::string_view channel_;
  TimeUs last_us_ = 0;
};

// ASC's date: "Tue Nov 24 06:30:55.123 am 2026", in UTC.
std::string asc_date(TimeUs t) {
  const std::time_t sec = static_cast<std::time_t>(t / fw::kUsPerS);
  std::tm tm{};
  gmtime_r(&sec, &tm);
  char head[32], tail[16];
  std::strftime(head, sizeof head, "%a %b %d %I:%M:%S", &tm);
  std::strftime(tail, sizeof tail, "%Y", &tm);
  char out[64];
  std::snprintf(out, sizeof out, "%s.%03d %s %s", head, static_cast<int>(t % fw::kUsPerS / 1000),
                tm.tm_hour < 12 ? "am" : "pm", tail);
  return out;
}

class AscWriter final : public LogWriter {
 public:
  void add(TimeUs t, const CanFrame& f) override {
    if (!started_) {
      started_ = true;
      start_us_ = t;
      const std::string date = asc_date(t);
      text_ += "date " + date + "\nbase hex  timestamps absolute\ninternal events logged\n// version 9.0.0\n";
      text_ += "Begin Triggerblock " + date + "\n   0.000000 Start of measurement\n";
    }
    const TimeUs rel = t - start_us_;
    char buf[400];
    int n = std::snprintf(buf, sizeof buf, "%4lld.%06lld ", static_cast<long long>(rel / fw::kUsPerS),
                          static_cast<long long>(rel % fw::kUsPerS));
    char id[16];
    std::snprintf(id, sizeof id, f.extended ? "%Xx" : "%X", static_cast<unsigned>(f.id));
    auto at = [&] { return buf + n; };
    auto room = [&] { return sizeof buf - static_cast<std::size_t>(n); };
    if (f.error) {
      n += std::snprintf(at(), room(), f.fd ? "CANFD   1 Rx   ErrorFrame" : "1  ErrorFrame");
    } else if (f.fd) {
      const std::uint8_t dlc = fd_length_code(f.len);
      n += std::snprintf(at(), room(), "CANFD   1 Rx   %8s  %32s 1 0 %x %2u", id, "", dlc, f.remote ? 0u : f.len);
      if (!f.remote)
        for (unsigned i = 0; i < f.len; ++i) n += std::snprintf(at(), room(), " %02X", f.data[i]);
      n += std::snprintf(at(), room(), " %8d %4d %8X %8d %8d %8d %8d %8d", 0, 0, 0x3000, 0, 0, 0, 0, 0);
    } else if (f.remote) {
      n += std::snprintf(at(), room(), "1  %-15s Rx   r %x", id, f.len);
    } else {
      n += std::snprintf(at(), room(), "1  %-15s Rx   d %x", id, f.len);
      for (unsigned i = 0; i < f.len; ++i) n += std::snprintf(at(), room(), " %02X", f.data[i]);
    }
    text_.append(buf, static_cast<std::size_t>(n)).push_back('\n');
  }
  std::string finish() override {
    if (!started_) text_ += "date \nbase hex  timestamps absolute\ninternal events logged\nBegin Triggerblock\n";
    text_ += "End TriggerBlock\n";
    return std::move(text_);
  }

 private:
  bool started_ = false;
  TimeUs start_us_ = 0;
  std::string text_;
};

}  // namespace

bool is_asc_header_line(std::string_view line) {
  const Fields fields(line);
  const std::string_view first = fields[0];
  return iequals(first, "date") || iequals(first, "base") || istarts_with(first, "//") ||
         (iequals(first, "begin") && iequals(fields[1], "triggerblock")) ||
         (iequals(first, "end") && iequals(fields[1], "triggerblock")) ||
         (iequals(first, "internal") && iequals(fields[1], "events")) ||
         (iequals(first, "no") && iequals(fields[1], "internal"));
}

std::unique_ptr<frames::FrameSource> make_asc_source(File file) { return std::make_unique<AscSource>(std::move(file)); }
std::unique_ptr<LogWriter> make_asc_writer() { return std::make_unique<AscWriter>(); }

}  // namespace lptn::canfile
