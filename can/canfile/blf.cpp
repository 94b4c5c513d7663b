// Vector BLF (binary logging format), as CANoe, CANalyzer and python-can write it:
//   a 144-byte file header ("LOGG", sizes, object count, start and stop as Windows SYSTEMTIME);
//   then objects, each "LOBJ", header size, header version, object size, object type, padded to
//   object size % 4 bytes. Log containers (type 10) hold further objects, zlib-deflated or plain;
//   an object may continue in the next container.
//   Inner objects have a header of version 1 or 2 whose time stamp counts from the file's start in
//   10 us (flag 1) or 1 ns (flag 2). CAN frames: CAN_MESSAGE (1), CAN_MESSAGE2 (86),
//   CAN_FD_MESSAGE (100), CAN_FD_MESSAGE_64 (101); CAN_ERROR_EXT (73) is an error frame. Other
//   objects carry no frame and are passed over.
// All numbers little-endian. The start time is read as UTC.
#include <zlib.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "hostio/civil_time.hpp"
#include "can/canfile/internal/formats.hpp"
#include "can/canfile/internal/inflate.hpp"

namespace lptn::canfile {
namespace {

using fw::CanFrame;
using frames::FrameSource;
using fw::TimeUs;

constexpr std::size_t kFileHeaderSize = 144;
constexpr std::size_t kBaseHeaderSize = 16;   // "LOBJ", header size, version, object size, type
constexpr std::size_t kV1HeaderSize = 16;     // flags, client index, object version, time stamp
constexpr std::size_t kContainerHeaderSize = 16;  // method, uncompressed size
// Larger than any real object or container (python-can and CANoe write containers of 128 KiB).
constexpr std::uint32_t kMaxObjectSize = 64u << 20;

enum ObjectType : std::uint32_t {
  kCanMessage = 1,
  kLogContainer = 10,
  kCanErrorExt = 73,
  kCanMessage2 = 86,
  kCanFdMessage = 100,
  kCanFdMessage64 = 101,
};
constexpr std::uint32_t kExtendedIdFlag = 0x80000000u;
constexpr std::uint32_t kTimeTenMicroseconds = 1;
constexpr std::uint32_t kTimeOneNanosecond = 2;
// No log spans more; beyond it the time stamp is damaged (and the sum with the start would overflow).
constexpr std::uint64_t kMaxOffsetUs = 100ull * 366 * 86400 * 1000000;

template <class T>
T get(const std::uint8_t* p) {
  T v = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) v = static_cast<T>(v | static_cast<T>(static_cast<T>(p[i]) << (8 * i)));
  return v;
}

template <class T>
void put(std::string& out, T v) {
  for (std::size_t i = 0; i < sizeof(T); ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

bool is_signature(const std::uint8_t* p) { return std::memcmp(p, "LOBJ", 4) == 0; }

// SYSTEMTIME (year, month, day of week, day, hour, minute, second, milliseconds) -> us since 1970;
// 0 where it is no date (python-can writes zeros for time stamps before 1990).
TimeUs systemtime_us(const std::uint8_t* p) {
  const unsigned year = get<std::uint16_t>(p), month = get<std::uint16_t>(p + 2), day = get<std::uint16_t>(p + 6);
  const unsigned hour = get<std::uint16_t>(p + 8), minute = get<std::uint16_t>(p + 10),
                 second = get<std::uint16_t>(p + 12), ms = get<std::uint16_t>(p + 14);
  if (year < 1970 || month < 1 || month > 12 || day < 1 || day > 31 || hour > 23 || minute > 59 || second > 60 ||
      ms > 999)
    return 0;
  const long long s = hostio::days_from_civil(year, month, day) * 86400 + hour * 3600 + minute * 60 + second;
  return static_cast<TimeUs>(s) * fw::kUsPerS + static_cast<TimeUs>(ms) * 1000;
}

void put_systemtime(std::string& out, TimeUs t) {
  const std::time_t sec = static_cast<std::time_t>(t / fw::kUsPerS);
  std::tm tm{};
  gmtime_r(&sec, &tm);
  for (int v : {tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_wday, tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec,
                static_cast<int>(t % fw::kUsPerS / 1000)})
    put(out, static_cast<std::uint16_t>(v));
}

class BlfSource final : public FrameSource {
 public:
  BlfSource(File file, const std::filesystem::path& path) : file_(std::move(file)) {
    std::uint8_t head[kFileHeaderSize];
    if (std::fread(head, 1, 72, file_.get()) != 72 || std::memcmp(head, kBlfMagic, 4) != 0)
      throw LogError(path.string() + ": not a BLF file (it does not start with \"LOGG\" and a file header)");
    const std::uint32_t header_size = get<std::uint32_t>(head + 4);
    if (header_size < 72 || header_size > 4096)
      throw LogError(path.string() + ": BLF file header size " + std::to_string(header_size) + " is not 72..4096 bytes");
    for (std::uint32_t skip = header_size - 72; skip > 0; --skip)
      if (std::fgetc(file_.get()) == EOF) throw LogError(path.string() + ": BLF file header is cut short");
    start_us_ = systemtime_us(head + 40);
  }

  Status next(TimeUs& time_us, CanFrame& frame, const char*& why) override {
    for (;;) {
      // Objects already unpacked from a container first.
      switch (inner(time_us, frame, why)) {
        case Inner::frame: return Status::frame;
        case Inner::bad: return Status::bad;
        case Inner::need_more: break;
      }
      switch (read_outer(why)) {
        case Outer::ok: break;
        case Outer::bad: return Status::bad;
        case Outer::end:
          if (pending_.size() > offset_ + 3) {  // a last object cut short
            offset_ = pending_.size();
            why = "the file ends inside an object";
            return Status::bad;
          }
          return Status::end;
      }
    }
  }
  std::size_t record() const override { return objects_; }
  const char* record_name() const override { return "object"; }
  std::string_view channel() const override { return std::string_view(channel_, channel_length_); }

 private:
  enum class Inner { frame, bad, need_more };
  enum class Outer { ok, bad, end };

  // The next outer object: a container's contents, or the object itself, onto pending_.
  Outer read_outer(const char*& why) {
    std::uint8_t base[kBaseHeaderSize];
    const std::size_t got = std::fread(base, 1, sizeof base, file_.get());
    if (got == 0) return Outer::end;
    ++objects_;
    if (got < sizeof base) {
      why = "the file ends inside an object header";
      return Outer::bad;
    }
    if (!is_signature(base)) {
      why = "no object signature \"LOBJ\" where an object should start; searching for the next";
      resync(base);
      return Outer::bad;
    }
    const std::uint32_t size = get<std::uint32_t>(base + 8), type = get<std::uint32_t>(base + 12);
    if (size < kBaseHeaderSize || size > kMaxObjectSize) {
      why = "object size is smaller than its header or larger than 64 MiB";
      return Outer::bad;
    }
    body_.resize(size - kBaseHeaderSize);
    if (std::fread(body_.data(), 1, body_.size(), file_.get()) != body_.size()) {
      why = "the file ends inside an object";
      return Outer::bad;
    }
    for (std::uint32_t pad = size % 4; pad > 0; --pad) std::fgetc(file_.get());
    compact();
    if (type != kLogContainer) {  // an object outside any container: parsed as one inside
      pending_.insert(pending_.end(), base, base + sizeof base);
      pending_.insert(pending_.end(), body_.begin(), body_.end());
      return Outer::ok;
    }
    if (body_.size() < kContainerHeaderSize) {
      why = "log container shorter than its header";
      return Outer::bad;
    }
    const std::uint16_t method = get<std::uint16_t>(body_.data());
    const std::uint32_t unpacked = get<std::uint32_t>(body_.data() + 8);
    const std::uint8_t* data = body_.data() + kContainerHeaderSize;
    const std::size_t packed = body_.size() - kContainerHeaderSize;
    if (method == 0) {
      pending_.insert(pending_.end(), data, data + packed);
      return Outer::ok;
    }
    if (method != 2) {
      why = "log container compressed by a method other than none (0) or zlib (2); skipped";
      return Outer::bad;
    }
    if (unpacked > kMaxObjectSize) {
      why = "log container larger than 64 MiB unpacked; skipped";
      return Outer::bad;
    }
    const std::size_t at = pending_.size();
    pending_.resize(at + unpacked);
    if (!inflater_.inflate_exactly(data, packed, pending_.data() + at, unpacked)) {
      pending_.resize(at);
      why = "log container does not inflate to its stated size (corrupt); skipped";
      return Outer::bad;
    }
    return Outer::ok;
  }

  // After a bad signature: read on to the next "LOBJ" and queue what follows as the next object.
  void resync(const std::uint8_t* seen) {
    std::uint8_t window[4] = {seen[12], seen[13], seen[14], seen[15]};
    for (int c; (c = std::fgetc(file_.get())) != EOF;) {
      std::memmove(window, window + 1, 3);
      window[3] = static_cast<std::uint8_t>(c);
      if (is_signature(window)) {
        // Put the signature back by reading the object from here on the next call.
        std::fseek(file_.get(), -4, SEEK_CUR);
        return;
      }
    }
  }

  void compact() {
    if (offset_ == 0) return;
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(offset_));
    offset_ = 0;
  }

  Inner inner(TimeUs& time_us, CanFrame& frame, const char*& why) {
    for (;;) {
      // Padding after the last object: up to 7 bytes before the next signature.
      std::size_t p = offset_;
      const std::size_t end = pending_.size();
      while (p + 4 <= end && p < offset_ + 8 && !is_signature(pending_.data() + p)) ++p;
      if (p + kBaseHeaderSize > end) return Inner::need_more;
      if (!is_signature(pending_.data() + p)) {
        // Lost inside a container: drop bytes up to the next signature.
        ++objects_;
        std::size_t q = p;
        while (q + 4 <= end && !is_signature(pending_.data() + q)) ++q;
        offset_ = q;
        why = "no object signature \"LOBJ\" inside a log container; searching for the next";
        return Inner::bad;
      }
      const std::uint8_t* o = pending_.data() + p;
      const std::uint16_t header_size = get<std::uint16_t>(o + 4), version = get<std::uint16_t>(o + 6);
      const std::uint32_t size = get<std::uint32_t>(o + 8), type = get<std::uint32_t>(o + 12);
      if (size < kBaseHeaderSize || size > kMaxObjectSize) {
        ++objects_;
        offset_ = p + 4;
        why = "object size is smaller than its header or larger than 64 MiB";
        return Inner::bad;
      }
      if (p + size > end) return Inner::need_more;  // continues in the next container
      offset_ = p + size;
      ++objects_;
      if (type != kCanMessage && type != kCanMessage2 && type != kCanFdMessage && type != kCanFdMessage64 &&
          type != kCanErrorExt)
        continue;  // no frame (markers, statistics, other buses)
      if ((version != 1 && version != 2) || header_size < kBaseHeaderSize + kV1HeaderSize || header_size > size) {
        why = "CAN object with an object header of unknown version or size";
        return Inner::bad;
      }
      const std::uint32_t flags = get<std::uint32_t>(o + 16);
      const std::uint64_t stamp = get<std::uint64_t>(o + 24);
      if (flags != kTimeTenMicroseconds && flags != kTimeOneNanosecond) {
        why = "object time stamp in a unit other than 10 us or 1 ns";
        return Inner::bad;
      }
      const std::uint64_t offset = flags == kTimeTenMicroseconds ? stamp : stamp / 1000 + (stamp % 1000 >= 500);
      if (offset > kMaxOffsetUs / (flags == kTimeTenMicroseconds ? 10 : 1)) {
        why = "object time stamp more than a century after the file's start";
        return Inner::bad;
      }
      const TimeUs offset_us = static_cast<TimeUs>(flags == kTimeTenMicroseconds ? offset * 10 : offset);
      if ((why = decode(type, o + header_size, size - header_size, frame)) != nullptr) return Inner::bad;
      // Every CAN object starts with its channel: 16 bits, but one byte in CAN_FD_MESSAGE_64.
      const std::uint8_t* body = o + header_size;
      const unsigned channel = type == kCanFdMessage64 ? body[0] : get<std::uint16_t>(body);
      // "%u" (to_chars: snprintf per frame was a fifth of BLF reading's own time).
      channel_length_ = static_cast<std::size_t>(std::to_chars(channel_, channel_ + sizeof channel_, channel).ptr - channel_);
      time_us = start_us_ + offset_us;
      return Inner::frame;
    }
  }

  static const char* decode(std::uint32_t type, const std::uint8_t* b, std::size_t n, CanFrame& f) {
    f = CanFrame{};
    auto id = [&f](std::uint32_t raw) {
      f.extended = (raw & kExtendedIdFlag) != 0;
      f.id = raw & 0x1FFFFFFFu;
      if (!f.extended && f.id > 0x7FF) return false;
      return true;
    };
    const char* bad_id = "standard frame id above 0x7FF";
    switch (type) {
      case kCanMessage:
      case kCanMessage2: {
        if (n < 16) return "CAN message object too short";
        const std::uint8_t flags = b[2], dlc = b[3];
        if (!id(get<std::uint32_t>(b + 4))) return bad_id;
        f.remote = (flags & 0x80) != 0;
        f.len = std::min<std::uint8_t>(dlc, 8);
        if (!f.remote) std::memcpy(f.data, b + 8, f.len);
        return nullptr;
      }
      case kCanFdMessage: {
        if (n < 84) return "CAN FD message object too short";
        const std::uint8_t flags = b[2], dlc = b[3], fd_flags = b[13], valid = b[14];
        if (!id(get<std::uint32_t>(b + 4))) return bad_id;
        f.fd = (fd_flags & 0x1) != 0;
        f.remote = (flags & 0x80) != 0;
        f.len = f.fd ? std::min<std::uint8_t>(valid, 64) : std::min<std::uint8_t>(dlc, 8);
        if (f.remote) f.len = f.fd ? kFdLengths[dlc & 15] : std::min<std::uint8_t>(dlc, 8);
        else std::memcpy(f.data, b + 20, f.len);
        return nullptr;
      }
      case kCanFdMessage64: {
        if (n < 40) return "CAN FD 64 message object too short";
        const std::uint8_t dlc = b[1], valid = b[2];
        if (!id(get<std::uint32_t>(b + 4))) return bad_id;
        const std::uint32_t flags = get<std::uint32_t>(b + 12);
        f.fd = (flags & 0x1000) != 0;
        f.remote = (flags & 0x10) != 0;
        if (f.remote) {
          f.len = f.fd ? kFdLengths[dlc & 15] : std::min<std::uint8_t>(dlc, 8);
          return nullptr;
        }
        f.len = std::min<std::uint8_t>(valid, f.fd ? 64 : 8);
        if (n < 40u + f.len) return "CAN FD 64 message object shorter than its data";
        std::memcpy(f.data, b + 40, f.len);
        return nullptr;
      }
      case kCanErrorExt: {
        if (n < 32) return "CAN error object too short";
        f.error = true;
        f.extended = (get<std::uint32_t>(b + 16) & kExtendedIdFlag) != 0;
        f.id = get<std::uint32_t>(b + 16) & 0x1FFFFFFFu;
        return nullptr;
      }
      default: return "not a CAN object";
    }
  }

  File file_;
  TimeUs start_us_ = 0;
  char channel_[8] = "";
  std::size_t channel_length_ = 0;
  std::vector<std::uint8_t> body_, pending_;
  Inflater inflater_;
  std::size_t offset_ = 0;   // into pending_
  std::size_t objects_ = 0;  // read so far, outer and inner
};

// Containers of 128 KiB unpacked, as python-can and CANoe write them.
class BlfWriter final : public LogWriter {
 public:
  void add(TimeUs t, const CanFrame& f) override {
    if (objects_ == 0) start_us_ = t - t % 1000;  // the header holds milliseconds
    stop_us_ = t;
    std::string body;
    std::uint32_t type;
    const std::uint32_t raw_id = f.id | (f.extended ? kExtendedIdFlag : 0u);
    if (f.error) {
      type = kCanErrorExt;
      put<std::uint16_t>(body, 1);  // channel
      put<std::uint16_t>(body, 0);  // length
      put<std::uint32_t>(body, 0);  // flags
      body.append(4, '\0');         // ecc, position, dlc, pad
      put<std::uint32_t>(body, 0);  // frame length
      put<std::uint32_t>(body, raw_id);
      put<std::uint16_t>(body, 0);  // extended flags
      body.append(2 + 8, '\0');
    } else if (f.fd) {
      type = kCanFdMessage;
      const std::uint8_t dlc = fd_length_code(f.len);
      put<std::uint16_t>(body, 1);
      body.push_back(static_cast<char>(f.remote ? 0x80 : 0));
      body.push_back(static_cast<char>(dlc));
      put<std::uint32_t>(body, raw_id);
      put<std::uint32_t>(body, 0);  // frame length
      body.push_back('\0');         // bit count
      body.push_back('\x01');       // EDL
      body.push_back(static_cast<char>(f.remote ? 0 : f.len));
      body.append(5, '\0');
      std::string data(64, '\0');
      if (!f.remote) std::memcpy(data.data(), f.data, f.len);
      body += data;
    } else {
      type = kCanMessage;
      put<std::uint16_t>(body, 1);
      body.push_back(static_cast<char>(f.remote ? 0x80 : 0));
      body.push_back(static_cast<char>(f.len));
      put<std::uint32_t>(body, raw_id);
      std::string data(8, '\0');
      if (!f.remote) std::memcpy(data.data(), f.data, std::min<std::size_t>(f.len, 8));
      body += data;
    }
    const std::uint32_t size = static_cast<std::uint32_t>(kBaseHeaderSize + kV1HeaderSize + body.size());
    buffer_ += "LOBJ";
    put<std::uint16_t>(buffer_, kBaseHeaderSize + kV1HeaderSize);
    put<std::uint16_t>(buffer_, 1);
    put<std::uint32_t>(buffer_, size);
    put<std::uint32_t>(buffer_, type);
    put<std::uint32_t>(buffer_, kTimeOneNanosecond);
    put<std::uint16_t>(buffer_, 0);  // client index
    put<std::uint16_t>(buffer_, 0);  // object version
    put<std::uint64_t>(buffer_, static_cast<std::uint64_t>(t - start_us_) * 1000);
    buffer_ += body;
    buffer_.append(body.size() % 4, '\0');  // python-can's padding, which its reader and ours skip
    ++objects_;
    while (buffer_.size() >= kContainer) flush(kContainer);
  }

  std::string finish() override {
    flush(buffer_.size());
    std::string head = kBlfMagic;
    put<std::uint32_t>(head, kFileHeaderSize);
    for (int v : {0, 0, 0, 0, 2, 6, 8, 1}) head.push_back(static_cast<char>(v));  // application, BL version
    put<std::uint64_t>(head, kFileHeaderSize + out_.size());
    put<std::uint64_t>(head, uncompressed_);
    put<std::uint32_t>(head, static_cast<std::uint32_t>(objects_));
    put<std::uint32_t>(head, 0);
    put_systemtime(head, start_us_);
    put_systemtime(head, objects_ ? stop_us_ : start_us_);
    head.resize(kFileHeaderSize, '\0');
    return head + out_;
  }

 private:
  static constexpr std::size_t kContainer = 128 * 1024;

  void flush(std::size_t n) {
    if (n == 0) return;
    uLongf packed_size = compressBound(static_cast<uLong>(n));
    std::string packed(packed_size, '\0');
    compress2(reinterpret_cast<Bytef*>(packed.data()), &packed_size, reinterpret_cast<const Bytef*>(buffer_.data()),
              static_cast<uLong>(n), 6);
    packed.resize(packed_size);
    const std::uint32_t size = static_cast<std::uint32_t>(kBaseHeaderSize + kContainerHeaderSize + packed.size());
    out_ += "LOBJ";
    put<std::uint16_t>(out_, kBaseHeaderSize);
    put<std::uint16_t>(out_, 1);
    put<std::uint32_t>(out_, size);
    put<std::uint32_t>(out_, kLogContainer);
    put<std::uint16_t>(out_, 2);  // zlib
    out_.append(6, '\0');
    put<std::uint32_t>(out_, static_cast<std::uint32_t>(n));
    out_.append(4, '\0');
    out_ += packed;
    out_.append(size % 4, '\0');
    uncompressed_ += kBaseHeaderSize + kContainerHeaderSize + n;
    buffer_.erase(0, n);
  }

  TimeUs start_us_ = 0, stop_us_ = 0;
  std::size_t objects_ = 0;
  std::uint64_t uncompressed_ = kFileHeaderSize;
  std::string buffer_, out_;
};

}  // namespace

std::unique_ptr<frames::FrameSource> make_blf_source(File file, const std::filesystem::path& path) {
  return std::make_unique<BlfSource>(std::move(file), path);
}
std::unique_ptr<LogWriter> make_blf_writer() { return std::make_unique<BlfWriter>(); }

}  // namespace lptn::canfile
