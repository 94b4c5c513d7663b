#include "record.hpp"

#include <algorithm>
#include <fstream>
#include <stdexcept>
#include <string>

#include "lptn/firmware/candump_line.hpp"

namespace lptn::fw {

bool same_frame(const CanFrame& a, const CanFrame& b) {
  return a.id == b.id && a.extended == b.extended && a.len == b.len && a.remote == b.remote && a.error == b.error &&
         a.fd == b.fd && std::equal(a.data, a.data + a.len, b.data);
}

RecordReplay replay_record(const std::filesystem::path& record, Estimator<double>& estimator,
                           const OutputId (&ids)[kMaxOutputFrames]) {
  std::ifstream in(record);
  if (!in) throw std::runtime_error(record.string() + ": cannot read the record");
  RecordReplay r;
  CanFrame expected[kMaxOutputFrames];
  int made = 0, next = 0;
  bool differs = false, ticked = false;
  TimeUs tick_time = 0;
  const auto close_tick = [&] {
    if (ticked && (differs || next != made) && r.ticks_differing++ == 0) r.first_differing = r.ticks;
  };
  for (std::string line; std::getline(in, line);) {
    CandumpRecord rec;
    if (parse_candump_line(line, rec) != nullptr) {
      ++r.bad_lines;
      continue;
    }
    if (rec.interface == "rx") {
      estimator.receive(rec.frame, rec.time_us);
      ++r.received;
      continue;
    }
    if (rec.interface == "overrun") {
      estimator.note_overrun();
      ++r.overruns;
      continue;
    }
    if (rec.interface != "tx") {
      ++r.bad_lines;
      continue;
    }
    if (!ticked || rec.time_us != tick_time) {  // the first of a tick's frames
      close_tick();
      tick_time = rec.time_us;
      ticked = true;
      ++r.ticks;
      made = pack_outputs(estimator.tick(tick_time), expected, ids);
      next = 0;
      differs = false;
    }
    differs = differs || next >= made || !same_frame(rec.frame, expected[next]);
    ++next;
  }
  close_tick();
  return r;
}

}  // namespace lptn::fw
