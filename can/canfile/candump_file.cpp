// candump -L logs: the CAN wing's candump source (can/frames/frame_source.hpp) on a reader of
// blocks; the writer formats lines as candump_line.hpp does.
#include "lptn/firmware/candump_line.hpp"
#include "can/canfile/internal/block_line_reader.hpp"
#include "can/canfile/internal/formats.hpp"

namespace lptn::canfile {
namespace {

// The file is held by a base constructed before the reader that reads it (a member would be
// constructed after the base CandumpLines).
struct HeldFile {
  File file;
};
class OwningCandumpSource final : private HeldFile, public frames::CandumpLines<BlockLineReader> {
 public:
  explicit OwningCandumpSource(File f) : HeldFile{std::move(f)}, frames::CandumpLines<BlockLineReader>(file.get()) {}
};

class CandumpWriter final : public LogWriter {
 public:
  explicit CandumpWriter(std::string interface) : interface_(std::move(interface)) {}
  void add(fw::TimeUs t, const fw::CanFrame& f) override {
    if (add_fast(t, f)) return;
    char line[200];
    const std::size_t n = fw::format_candump_line(line, sizeof line, t, interface_, f);
    if (n == 0) throw LogError("interface '" + interface_ + "': too long for a candump line");
    text_.append(line, n).push_back('\n');
  }
  std::string finish() override { return std::move(text_); }

 private:
  // format_candump_line's bytes without snprintf (which was most of `lptn convert`'s time) for
  // what a converter sends: classic data frames, standard or extended, at a time stamp of at most
  // ten digits of seconds. Anything else (remote, error, FD frames) goes the shared way.
  bool add_fast(fw::TimeUs t, const fw::CanFrame& f) {
    if (f.remote || f.error || f.fd || f.len > 8 || t < 0 || t >= 10000000000LL * fw::kUsPerS || interface_.size() > 100)
      return false;
    if (f.extended ? f.id > 0x1FFFFFFFu : f.id > 0xFFFu) return false;
    static constexpr char kHex[] = "0123456789ABCDEF";
    char line[64 + 16];
    char* p = line;
    *p++ = '(';
    auto digits = [&p](long long v, int n) {
      for (int i = n - 1; i >= 0; --i) {
        p[i] = static_cast<char>('0' + v % 10);
        v /= 10;
      }
      p += n;
    };
    digits(t / fw::kUsPerS, 10);
    *p++ = '.';
    digits(t % fw::kUsPerS, 6);
    *p++ = ')';
    *p++ = ' ';
    text_.append(line, static_cast<std::size_t>(p - line));
    text_.append(interface_);
    p = line;
    *p++ = ' ';
    for (int shift = f.extended ? 28 : 8; shift >= 0; shift -= 4) *p++ = kHex[f.id >> shift & 0xF];
    *p++ = '#';
    for (unsigned i = 0; i < f.len; ++i) {
      *p++ = kHex[f.data[i] >> 4];
      *p++ = kHex[f.data[i] & 0xF];
    }
    *p++ = '\n';
    text_.append(line, static_cast<std::size_t>(p - line));
    return true;
  }


  std::string interface_, text_;
};

}  // namespace

std::unique_ptr<frames::FrameSource> make_candump_source(File file) {
  return std::make_unique<OwningCandumpSource>(std::move(file));
}
std::unique_ptr<LogWriter> make_candump_writer(const std::string& interface) {
  return std::make_unique<CandumpWriter>(interface);
}

}  // namespace lptn::canfile
