#include "tools/replay/replay_to_csv.hpp"

#include <cstdio>
#include <memory>
#include <stdexcept>

#include "atomic_file.hpp"
#include "estimate_csv.hpp"
#include "tools/cli/progress.hpp"

namespace lptn {

fw::ReplayStats replay_to_csv(const std::string& log_path, const fw::EstimatorConfig<double>& config,
                              const std::string& csv_path, bool quiet) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> log(std::fopen(log_path.c_str(), "r"), &std::fclose);
  if (!log) throw std::invalid_argument(log_path + ": cannot be opened");
  fw::AtomicFile csv;
  if (!csv.open(csv_path)) throw std::invalid_argument(csv_path + ": cannot be written");
  auto estimator = std::make_unique<fw::Estimator<double>>(config);
  fw::write_estimate_header(csv.get());
  cli::ProgressLine progress(quiet);
  fw::ReplaySinks sinks;
  sinks.row = [&](const fw::EstimatorOutput<double>& o, fw::TimeUs start) { fw::write_estimate_row(csv.get(), o, start); };
  sinks.bad_line = [&](std::size_t line, const char* why) {
    progress.finish();
    std::fprintf(stderr, "%s:%zu: %s (line skipped)\n", log_path.c_str(), line, why);
  };
  sinks.progress_every = 200000;
  sinks.progress = [&](const fw::ReplayStats& s) {
    progress.update("replay: " + std::to_string(s.frames) + " frames, " +
                    cli::ProgressLine::clock(static_cast<double>(s.last_us - s.first_us) / 1e6) + " of log");
  };
  const fw::ReplayStats stats = fw::replay_candump(log.get(), *estimator, sinks);
  progress.finish();
  if (stats.frames == 0) throw std::invalid_argument(log_path + ": no CAN frame could be read");
  if (!csv.commit()) throw std::runtime_error(csv_path + ": writing failed");
  return stats;
}

}  // namespace lptn
