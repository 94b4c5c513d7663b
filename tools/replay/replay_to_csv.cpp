#include "tools/replay/replay_to_csv.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "hostio/atomic_file.hpp"
#include "firmware/linux/estimate_csv.hpp"
#include "hostio/progress_line.hpp"

namespace lptn::replay {
namespace {

// Numbers appended one at a time and read back by index, in blocks of 64 Ki that are never moved:
// a vector's doublings copied each number and touched twice the pages it ends with (two thirds
// of a replay's page faults).
class Column {
 public:
  void push_back(double v) {
    if (used_ == kBlock) {
      blocks_.push_back(std::make_unique_for_overwrite<double[]>(kBlock));
      used_ = 0;
    }
    blocks_.back()[used_++] = v;
  }
  std::size_t size() const { return blocks_.empty() ? 0 : (blocks_.size() - 1) * kBlock + used_; }
  double operator[](std::size_t k) const { return blocks_[k / kBlock][k % kBlock]; }

 private:
  static constexpr std::size_t kBlock = std::size_t{1} << 16;
  std::vector<std::unique_ptr<double[]>> blocks_;
  std::size_t used_ = kBlock;
};

// One node's track: the estimate, its spread and the fresh reading (NaN: none) per tick.
struct Track {
  Column estimate, spread, reading;
  void add(double e, double s, double y) {
    estimate.push_back(e);
    spread.push_back(s);
    reading.push_back(y);
  }
};

constexpr std::size_t kNoiseLagTicks = 20;  // 2 s at the 0.1 s step (BandCoverage says why)

BandCoverage coverage_of(const Track& t) {
  BandCoverage c;
  const Column& y = t.reading;
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t k = 0; k + 2 * kNoiseLagTicks < y.size(); ++k) {
    const double d = y[k] - 2 * y[k + kNoiseLagTicks] + y[k + 2 * kNoiseLagTicks];
    if (std::isnan(d)) continue;
    sum += d * d;
    ++n;
  }
  if (n == 0) return c;  // too few readings to know their noise: no coverage claimed
  c.sensor_noise_k = std::sqrt(sum / static_cast<double>(n) / 6.0);
  for (std::size_t k = 0; k < y.size(); ++k) {
    if (std::isnan(y[k])) continue;
    ++c.ticks;
    const double band = 2 * std::sqrt(t.spread[k] * t.spread[k] + c.sensor_noise_k * c.sensor_noise_k);
    if (std::abs(t.estimate[k] - y[k]) <= band) ++c.within;
  }
  return c;
}

}  // namespace

ReplaySummary replay_to_csv(const std::string& log_path, const fw::EstimatorConfig<double>& config,
                              const std::string& csv_path, bool quiet, const canfile::LogSelection& select,
                              data::NameplateCheck* inputs_check) {
  ReplaySummary summary;
  std::unique_ptr<canfile::ChannelFilter> log;
  try {
    canfile::OpenedLog opened = canfile::open_log(log_path, select);
    summary.format = opened.format;
    log = std::move(opened.frames);
  } catch (const canfile::LogError& e) {
    throw std::invalid_argument(e.what());
  }
  hostio::AtomicFile csv;
  if (!csv.open(csv_path)) throw std::invalid_argument(csv_path + ": cannot be written");
  auto estimator = std::make_unique<fw::Estimator<double>>(config);
  fw::write_estimate_header(csv.get());
  // Rows are formatted into a buffer of 1 MiB (not zeroed first: every byte written is written
  // before it is read) and written a buffer at a time.
  constexpr std::size_t kOut = std::size_t{1} << 20;
  const std::unique_ptr<char[]> out = std::make_unique_for_overwrite<char[]>(kOut);
  std::size_t used = 0;
  auto flush = [&] {
    std::fwrite(out.get(), 1, used, csv.get());
    used = 0;
  };
  fw::EstimateRowFormatter rows;
  hostio::ProgressLine progress(quiet);
  fw::ReplaySinks sinks;
  double sum_stator = 0, sum_rotor = 0;
  Track stator, rotor;
  sinks.row = [&](const fw::EstimatorOutput<double>& o, fw::TimeUs start) {
    if (kOut - used < fw::kMaxEstimateRow) flush();
    used += rows.format(out.get() + used, o, start);
    if (inputs_check) {
      const fw::InputConditioner<double>& bus = estimator->input_conditioner();
      inputs_check->add(static_cast<float>(bus.last_received(fw::Input::speed)),
                        static_cast<float>(bus.last_received(fw::Input::current)),
                        static_cast<float>(bus.last_received(fw::Input::frequency)),
                        static_cast<float>(bus.last_received(fw::Input::voltage)));
    }
    summary.inputs.add(o);
    summary.cooling_factor = o.cooling_factor;
    summary.cooling_factor_std = o.cooling_factor_std;
    summary.cooling_state = o.cooling_state;
    if (o.cooling_alarm && summary.cooling_alarm_from_s < 0)
      summary.cooling_alarm_from_s = static_cast<double>(o.time_us - start) / 1e6;
    stator.add(o.node_c[kStatorWinding], o.node_std_k[kStatorWinding], o.stator_reading_c);
    rotor.add(o.node_c[kRotorWinding], o.node_std_k[kRotorWinding], o.rotor_reading_c);
    if (!std::isnan(o.stator_reading_c)) {
      sum_stator += (o.node_c[kStatorWinding] - o.stator_reading_c) * (o.node_c[kStatorWinding] - o.stator_reading_c);
      ++summary.stator_samples;
    }
    if (!std::isnan(o.rotor_reading_c)) {
      sum_rotor += (o.node_c[kRotorWinding] - o.rotor_reading_c) * (o.node_c[kRotorWinding] - o.rotor_reading_c);
      ++summary.rotor_samples;
    }
  };
  // A garbage file should not bury the terminal; the count at the end says how many more there were.
  std::size_t bad = 0;
  sinks.bad_record = [&](std::size_t record, const char* why) {
    if (++bad > canfile::kRecordMessagesShown) return;
    progress.finish();
    std::fprintf(stderr, "%s (%s skipped)\n", canfile::record_message(log_path, *log, record, why).c_str(),
                 log->record_name());
  };
  sinks.progress_every = 200000;
  sinks.progress = [&](const fw::ReplayStats& s) {
    progress.update("replay: " + std::to_string(s.frames) + " frames, " +
                    hostio::ProgressLine::clock(static_cast<double>(s.last_us - s.first_us) / 1e6) + " of log");
  };
  const auto start = std::chrono::steady_clock::now();
  summary.stats = fw::replay_frames(*log, *estimator, sinks);
  flush();
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  progress.finish();
  if (bad > canfile::kRecordMessagesShown)
    std::fprintf(stderr, "%s: %zu more malformed %ss skipped\n", log_path.c_str(), bad - canfile::kRecordMessagesShown,
                 log->record_name());
  if (summary.stator_samples) summary.rmse_stator_k = std::sqrt(sum_stator / static_cast<double>(summary.stator_samples));
  if (summary.rotor_samples) summary.rmse_rotor_k = std::sqrt(sum_rotor / static_cast<double>(summary.rotor_samples));
  summary.stator_coverage = coverage_of(stator);
  summary.rotor_coverage = coverage_of(rotor);
  bool fatal = false;
  const std::string channels = canfile::channel_problem(log_path, *log, select, fatal);
  if (fatal) throw std::invalid_argument(channels);
  if (!channels.empty()) std::fprintf(stderr, "lptn: warning: %s\n", channels.c_str());
  if (summary.stats.frames == 0)
    throw std::invalid_argument(log_path + ": no CAN frame could be read (as " + canfile::format_name(summary.format) +
                                "; --format names another)");
  if (!csv.commit()) throw std::runtime_error(csv_path + ": writing failed");
  return summary;
}

}  // namespace lptn::replay
