// candump -L logs: the reader is the firmware's own (firmware/linux/frame_source.hpp), which owns
// no file; the writer formats lines as lptn/firmware/candump_line.hpp does.
#include "lptn/firmware/candump_line.hpp"
#include "tools/canfile/internal/formats.hpp"

namespace lptn::canfile {
namespace {

class OwningCandumpSource final : public fw::FrameSource {
 public:
  explicit OwningCandumpSource(File file) : file_(std::move(file)), source_(file_.get()) {}
  Status next(fw::TimeUs& time_us, fw::CanFrame& frame, const char*& why) override {
    return source_.next(time_us, frame, why);
  }
  std::size_t record() const override { return source_.record(); }
  const char* record_name() const override { return source_.record_name(); }
  std::string_view channel() const override { return source_.channel(); }

 private:
  File file_;
  fw::CandumpSource source_;
};

class CandumpWriter final : public LogWriter {
 public:
  explicit CandumpWriter(std::string interface) : interface_(std::move(interface)) {}
  void add(fw::TimeUs t, const fw::CanFrame& f) override {
    char line[200];
    const std::size_t n = fw::format_candump_line(line, sizeof line, t, interface_, f);
    if (n == 0) throw LogError("interface '" + interface_ + "': too long for a candump line");
    text_.append(line, n).push_back('\n');
  }
  std::string finish() override { return std::move(text_); }

 private:
  std::string interface_, text_;
};

}  // namespace

std::unique_ptr<fw::FrameSource> make_candump_source(File file) {
  return std::make_unique<OwningCandumpSource>(std::move(file));
}
std::unique_ptr<LogWriter> make_candump_writer(const std::string& interface) {
  return std::make_unique<CandumpWriter>(interface);
}

}  // namespace lptn::canfile
