// Fleet-dump CSV -> CAN log (candump, ASC, BLF).

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <type_traits>
#include <algorithm>
#include <optional>
#include <vector>

#include "can/canlog/bus_channels.hpp"
#include "can/canlog/convert.hpp"
#include "can/canfile/can_log.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/data/source_line.hpp"

namespace lptn::canlog {
namespace {

namespace fs = std::filesystem;

static_assert(data::kDefaultDtS * 1e6 == kGridStepUs, "the frames' schedule assumes the loader's grid");

// PulsesEnabled is no column of the contract: the converter's pulses are on while current flows.
constexpr double kPulsesOnAboveA = 0.5;

template <class Msg>
[[noreturn]] void out_of_range(const fs::path& csv, const char* message, const ChannelSignal<Msg>& s, double value,
                               double t) {
  const std::size_t line = data::line_of_sample_outside(csv, s.channel, t, s.min, s.max);
  const std::string where = line ? csv.string() + ":" + std::to_string(line) : csv.string();
  char reason[256];
  std::snprintf(reason, sizeof reason, "%g at t=%.3f s is outside %.*s's range [%g, %g] (%s)", value, t,
                static_cast<int>(s.signal.size()), s.signal.data(), s.min, s.max, message);
  throw ConvertError(where + ": column '" + std::string(data::channel_name(s.channel)) + "': " + reason);
}

// Schedules the frames, in time order, keeping each message's alive counter.
class FrameSchedule {
 public:
  FrameSchedule(const fs::path& csv, const LogOptions& options)
      : csv_(csv), options_(options), writer_(canfile::make_log_writer(options.format, options.interface)) {}

  // Every message due at grid point g (counted from the first kept one), in phase order; k is the
  // same point in `cycle`.
  void grid_point(const data::Cycle& cycle, std::size_t k, std::size_t g) {
    std::size_t i = 0;
    for_each_input_message([&](const auto& m) { send(m, alive_[i++], cycle, k, g); });
  }

  std::size_t frames() const { return frames_; }
  std::string finish() { return writer_->finish(); }

 private:
  template <class M>
  void send(const M& m, std::uint32_t& alive, const data::Cycle& cycle, std::size_t k, std::size_t g) {
    using Msg = typename M::Frame;
    if (g % M::kGridStride != 0) return;
    Msg msg{};
    for (const auto& s : m.signals) {
      const double v = cycle.at(s.channel, k);
      if (std::isnan(v)) return;  // a frame carries all of its columns or is not sent
      if (!(v >= s.min && v <= s.max)) out_of_range(csv_, Msg::kName, s, v, cycle.time_s(k));
      s.encode(msg, v);
    }
    if constexpr (std::is_same_v<Msg, can::TcElectrical>)
      msg.pulses_enabled = Msg::pulses_enabled_encode(cycle.at(data::Channel::current_a, k) > kPulsesOnAboveA ? 1 : 0);
    msg.alive_counter = Msg::alive_counter_encode(alive);
    alive = (alive + 1) % (1u << signal_info<Msg>("AliveCounter").length);
    put(options_.start_us + static_cast<TimeUs>(g) * kGridStepUs + m.phase_us, fw::to_frame(msg));
  }

  void put(TimeUs t, const fw::CanFrame& f) {
    try {
      writer_->add(t, f);
    } catch (const canfile::LogError& e) {
      throw ConvertError(std::string("--interface: ") + e.what());
    }
    ++frames_;
  }

  const fs::path& csv_;
  const LogOptions& options_;
  std::array<std::uint32_t, std::tuple_size_v<decltype(bus::kInputMessages)>> alive_{};
  std::unique_ptr<canfile::LogWriter> writer_;
  std::size_t frames_ = 0;
};

// The frames of a run-time bus map: each mapped message every cycle time, its multiplexor values
// one after another, each message's alive counter counting the frames of it sent.
class BusFrameSchedule {
 public:
  BusFrameSchedule(const fs::path& csv, const LogOptions& options)
      : csv_(csv), options_(options), map_(*options.bus), writer_(canfile::make_log_writer(options.format, options.interface)) {
    const auto& messages = map_.messages();
    alive_.assign(messages.size(), 0);
    for (std::size_t i = 0; i < messages.size(); ++i) {
      const lptn::bus::MappedMessage& m = messages[i];
      const std::uint64_t cycle_us = std::uint64_t{m.cycle_ms} * 1000;
      if (cycle_us % kGridStepUs != 0)
        throw ConvertError(map_.file().string() + ": " + m.message->name + "'s cycle time, " + std::to_string(m.cycle_ms) +
                           " ms, is not a whole number of the loader's 100 ms grid steps; give cycle_ms in [messages." +
                           m.message->name + "]");
      stride_.push_back(cycle_us / kGridStepUs);
      pages_.push_back(lptn::bus::BusMap::pages(m));
      for (const lptn::bus::MappedInput& in : m.inputs) {
        const std::optional<data::Channel> c = data::channel_from_name(in.column);
        if (!c) throw std::logic_error("bus vocabulary column is no fleet-dump column: " + in.column);
        channel_[fw::index_of(in.input)] = *c;
      }
    }
  }

  void grid_point(const data::Cycle& cycle, std::size_t k, std::size_t g) {
    const auto& messages = map_.messages();
    // Frames within a grid step: 1 ms apart, in the map's message order and multiplexor order.
    TimeUs phase = 0;
    for (std::size_t i = 0; i < messages.size(); ++i) {
      for (long long page : pages_[i]) {
        if (g % stride_[i] == 0) send(messages[i], i, page, cycle, k, g, phase);
        phase += 1000;
      }
    }
  }

  std::size_t frames() const { return frames_; }
  std::string finish() { return writer_->finish(); }

 private:
  void send(const lptn::bus::MappedMessage& m, std::size_t i, long long page, const data::Cycle& cycle, std::size_t k,
            std::size_t g, TimeUs phase) {
    double values[fw::kNumInputs]{};
    for (const lptn::bus::MappedInput& in : m.inputs) {
      if (in.signal->mux == dbc::Signal::Mux::multiplexed && in.signal->mux_value != page) continue;
      const double v = cycle.at(channel_[fw::index_of(in.input)], k);
      if (std::isnan(v)) return;  // a frame carries all of its columns or is not sent
      const double physical = (v - in.offset) / in.scale;
      const dbc::Signal& s = *in.signal;
      if (s.minimum < s.maximum && !(physical >= s.minimum && physical <= s.maximum)) {
        const data::Channel c = channel_[fw::index_of(in.input)];
        const double a = s.minimum * in.scale + in.offset, b = s.maximum * in.scale + in.offset;
        const std::size_t line = data::line_of_sample_outside(csv_, c, cycle.time_s(k), std::min(a, b), std::max(a, b));
        const std::string where = line ? csv_.string() + ":" + std::to_string(line) : csv_.string();
        char reason[320];
        std::snprintf(reason, sizeof reason, "%g at t=%.3f s is %g in %s.%s, outside its range [%g, %g] (%s)", v,
                      cycle.time_s(k), physical, m.message->name.c_str(), s.name.c_str(), s.minimum, s.maximum,
                      map_.file().string().c_str());
        throw ConvertError(where + ": column '" + in.column + "': " + reason);
      }
      values[fw::index_of(in.input)] = v;
    }
    const fw::CanFrame f = map_.encode(m, values, page, alive_[i]++);
    try {
      writer_->add(options_.start_us + static_cast<TimeUs>(g) * kGridStepUs + phase, f);
    } catch (const canfile::LogError& e) {
      throw ConvertError(std::string("--interface: ") + e.what());
    }
    ++frames_;
  }

  const fs::path& csv_;
  const LogOptions& options_;
  const lptn::bus::BusMap& map_;
  std::unique_ptr<canfile::LogWriter> writer_;
  std::vector<std::uint32_t> alive_;
  std::vector<std::uint64_t> stride_;
  std::vector<std::vector<long long>> pages_;
  data::Channel channel_[fw::kNumInputs]{};
  std::size_t frames_ = 0;
};

// Every grid point of every kept segment through `writer`. Segments of a split cycle keep their
// place on the file's grid, so the log has a silence where the loader cut, as a bus would.
template <class Schedule>
void schedule_cycles(const data::Dataset& dataset, Schedule& writer) {
  const double origin_s = dataset.cycles.front().t0_s;
  for (const data::Cycle& cycle : dataset.cycles) {
    const auto first = static_cast<std::size_t>(std::llround((cycle.t0_s - origin_s) / cycle.dt_s));
    for (std::size_t k = 0; k < cycle.steps; ++k) writer.grid_point(cycle, k, first + k);
  }
}

}  // namespace

Converted log_from_csv(const fs::path& csv, const LogOptions& options) {
  const data::Dataset dataset = data::load_cycle_file(csv, options.load);
  Converted out;
  for (const data::Finding& f : dataset.reports.front().findings)
    if (f.severity == data::Finding::Severity::warning) out.warnings.push_back(f.message);
  if (dataset.cycles.empty())
    throw ConvertError(csv.string() + ": no stretch of it has speed, current, frequency, airflow and ambient; "
                                      "nothing to send (see lptn inspect)");

  const data::Cycle& last = dataset.cycles.back();
  out.duration_s = last.t0_s + last.duration_s() - dataset.cycles.front().t0_s;
  if (options.bus) {
    BusFrameSchedule writer(csv, options);
    schedule_cycles(dataset, writer);
    out.frames = writer.frames();
    out.text = writer.finish();
  } else {
    FrameSchedule writer(csv, options);
    schedule_cycles(dataset, writer);
    out.frames = writer.frames();
    out.text = writer.finish();
  }
  return out;
}

}  // namespace lptn::canlog
