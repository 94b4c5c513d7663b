// log -> log: a CAN log written again in another format (an ASC or a logger's MDF4 as candump for
// canplayer, a candump log as MDF4 for asammdf), every frame as it was, nothing decoded.

#include <cstdio>
#include <string>

#include "can/canfile/can_log.hpp"
#include "can/canlog/convert.hpp"
#include "can/canlog/internal/open_for_conversion.hpp"

namespace lptn::canlog {

Converted log_from_log(const std::filesystem::path& log, const canfile::LogSelection& select, canfile::LogFormat to,
                       const std::string& interface) {
  const canfile::OpenedLog opened = internal::open_for_conversion(log, select);
  canfile::ChannelFilter& source = *opened.frames;
  const auto writer = canfile::make_log_writer(to, interface);
  Converted out;
  fw::TimeUs t = 0, first = 0, last = 0;
  fw::CanFrame frame;
  const char* why = nullptr;
  std::size_t bad = 0, backwards = 0, first_bad = 0, first_backwards = 0;
  std::string first_why;
  for (frames::FrameSource::Status s; (s = source.next(t, frame, why)) != frames::FrameSource::Status::end;) {
    if (s == frames::FrameSource::Status::bad) {
      if (bad++ == 0) {
        first_bad = source.record();
        first_why = why ? why : "";
      }
      continue;
    }
    // Every writer takes frames in time order; a frame stamped before the one before it is a
    // recorder's fault (or a merge of two buses), dropped and counted as log -> CSV does.
    if (out.frames > 0 && t < last) {
      if (backwards++ == 0) first_backwards = source.record();
      continue;
    }
    if (out.frames == 0) first = t;
    last = t;
    writer->add(t, frame);
    ++out.frames;
  }
  bool fatal = false;
  const std::string channels = canfile::channel_problem(log, source, select, fatal);
  if (fatal) throw ConvertError(channels);
  if (out.frames == 0)
    throw ConvertError(log.string() + ": no frame could be read (" + std::to_string(bad) + " " +
                       source.record_name() + "s dropped)");
  if (bad > 0)
    out.warnings.push_back(log.string() + ": " + std::to_string(bad) + " " + source.record_name() +
                           "s that are no frame dropped; the first, " + source.record_name() + " " +
                           std::to_string(first_bad) + ": " + first_why);
  if (backwards > 0)
    out.warnings.push_back(log.string() + ": " + std::to_string(backwards) + " frames stamped before the frame before "
                           "them dropped; the first, " + source.record_name() + " " + std::to_string(first_backwards));
  if (!channels.empty()) out.warnings.push_back(channels);
  out.duration_s = static_cast<double>(last - first) * 1e-6;
  out.text = writer->finish();
  return out;
}

}  // namespace lptn::canlog
