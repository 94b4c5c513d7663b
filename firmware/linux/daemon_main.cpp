// lptn-daemon: the estimator on the drive controller, with the calibration compiled in
// (calibration/default_calibration.hpp, an `lptn export`). Three ways to get frames:
//   --interface IF   a SocketCAN interface: kernel filters for the input ids, a monotonic timer
//                    ticks every dt (divided by --time-scale for accelerated benches), outputs
//                    are sent on the same interface every tick; SIGTERM/SIGINT stop it cleanly
//   --log FILE       a candump log played in (scaled) real time through the same timer loop;
//                    outputs written as candump lines to --out (default stdout)
//   --replay FILE    as fast as possible, time stamps driving the ticks (as `lptn replay`), the
//                    estimates as CSV to --csv; on stderr the counts and, as `lptn replay` says
//                    them, the inputs the model did not get as the log sent them
// With --interface or --log, --record FILE keeps what the estimator was given, in the order it was
// given it (PX4's replay log): every frame it received, stamped with the time the estimator was
// told, a receive-buffer overrun the kernel reported (interface overrun, an empty frame), and at
// every tick the frames the tick produced, stamped with the tick's time. Replaying a
// record through the estimator (lptn-vcan-bench does) must give the recorded frames bit for bit,
// however late the timer fired or the frames came.
#include <getopt.h>
#include <poll.h>
#include <sys/signalfd.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <string_view>
#include <iterator>

#include LPTN_CALIBRATION_HEADER  // firmware/CMakeLists.txt: an `lptn export`
#include "hostio/atomic_file.hpp"
#include "hostio/line_reader.hpp"
#include "estimate_csv.hpp"
#include "lptn/firmware/exported_calibration.hpp"
#include "lptn/firmware/output_frames.hpp"
#include "lptn/version.hpp"
#include "input_tally.hpp"
#include "replay.hpp"
#include "socketcan.hpp"

namespace {

using lptn::fw::TimeUs;
using lptn::fw::kUsPerS;

constexpr const char* kUsage =
    "usage: lptn-daemon (--interface IF | --log FILE | --replay FILE) [options]\n"
    "The lptn thermal estimator with its calibration compiled in.\n"
    "  --interface IF     read inputs from SocketCAN interface IF, send estimates on it every tick\n"
    "  --log FILE         take frames from a candump -L log, played in (scaled) real time\n"
    "  --replay FILE      replay a candump log as fast as possible (time stamps drive the ticks)\n"
    "  --csv FILE         with --replay: the estimates as CSV (default stdout)\n"
    "  --out FILE         with --log: the output frames as candump lines (default stdout)\n"
    "  --record FILE      with --interface or --log: every frame received (interface rx, stamped with the\n"
    "                     estimator's time) and every tick's frames (interface tx, the tick's time), as\n"
    "                     candump -L lines in the order the estimator saw them\n"
    "  --time-scale S     run S times faster than real time (timer and ages scaled; default 1)\n"
    "  --duration S       stop after S seconds of estimator time (default: until SIGTERM or log end)\n"
    "  --open-loop        do not fuse the stator winding sensor\n"
    "  --use-actor        let the calibration's TD3 actor schedule the parameters (needs torque)\n"
    "  --help, --version\n"
    "Exit: 0 after SIGTERM/SIGINT or the end of the input, 1 on a runtime failure (the interface removed among\n"
    "them; what was received until then is recorded), 2 on bad arguments.\n";

struct Options {
  std::string interface, log, replay, csv, out, record;
  double time_scale = 1.0;
  double duration_s = 0.0;
  bool open_loop = false, use_actor = false;
};

int usage_error(const char* what) {
  std::fprintf(stderr, "lptn-daemon: error: %s (see --help)\n", what);
  return 2;
}

bool parse_number(const char* text, double& out) {
  char* end = nullptr;
  errno = 0;
  out = std::strtod(text, &end);
  return errno == 0 && end != text && *end == '\0';
}

// 0 to go on, otherwise the exit code.
int parse_options(int argc, char** argv, Options& o) {
  static const option kLong[] = {{"interface", required_argument, nullptr, 'i'}, {"log", required_argument, nullptr, 'l'},
                                 {"replay", required_argument, nullptr, 'r'},    {"csv", required_argument, nullptr, 'c'},
                                 {"out", required_argument, nullptr, 'o'},       {"time-scale", required_argument, nullptr, 's'},
                                 {"duration", required_argument, nullptr, 'd'},  {"open-loop", no_argument, nullptr, 'L'},
                                 {"use-actor", no_argument, nullptr, 'A'},       {"help", no_argument, nullptr, 'h'},
                                 {"version", no_argument, nullptr, 'V'},         {"record", required_argument, nullptr, 'R'},
                                 {nullptr, 0, nullptr, 0}};
  opterr = 0;
  int c;
  while ((c = getopt_long(argc, argv, "", kLong, nullptr)) != -1) {
    switch (c) {
      case 'i': o.interface = optarg; break;
      case 'l': o.log = optarg; break;
      case 'r': o.replay = optarg; break;
      case 'c': o.csv = optarg; break;
      case 'o': o.out = optarg; break;
      case 'R': o.record = optarg; break;
      case 's':
        if (!parse_number(optarg, o.time_scale) || !(o.time_scale > 0)) return usage_error("--time-scale: expected a number > 0");
        break;
      case 'd':
        if (!parse_number(optarg, o.duration_s) || !(o.duration_s > 0)) return usage_error("--duration: expected seconds > 0");
        break;
      case 'L': o.open_loop = true; break;
      case 'A': o.use_actor = true; break;
      case 'h': std::fputs(kUsage, stdout); return -1;
      case 'V': std::printf("lptn-daemon %s (calibration: %s, %s)\n", lptn::kVersion, lptn::calibration::kMethod, lptn::calibration::kCreatedUtc); return -1;
      default: return usage_error(argv[optind - 1] ? argv[optind - 1] : "bad option");
    }
  }
  if (optind < argc) return usage_error(argv[optind]);
  const int sources = !o.interface.empty() + !o.log.empty() + !o.replay.empty();
  if (sources != 1) return usage_error("give exactly one of --interface, --log, --replay");
  if (!o.csv.empty() && o.replay.empty()) return usage_error("--csv goes with --replay");
  if (!o.out.empty() && o.log.empty()) return usage_error("--out goes with --log");
  if (!o.record.empty() && !o.replay.empty()) return usage_error("--record goes with --interface or --log");
  return 0;
}

lptn::fw::EstimatorConfig<double> make_config(const Options& o) {
  auto config = lptn::fw::config_from_exported_header<double>();
  config.fuse_stator_sensor = !o.open_loop;
  config.use_actor = o.use_actor;
  return config;
}

TimeUs monotonic_us() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<TimeUs>(ts.tv_sec) * kUsPerS + ts.tv_nsec / 1000;
}

int run_replay(const Options& o) {
  std::FILE* log = std::fopen(o.replay.c_str(), "r");
  if (!log) {
    std::fprintf(stderr, "lptn-daemon: error: %s: %s\n", o.replay.c_str(), std::strerror(errno));
    return 2;
  }
  lptn::hostio::AtomicFile csv;
  if (!csv.open(o.csv)) {
    std::fprintf(stderr, "lptn-daemon: error: %s: %s\n", o.csv.c_str(), std::strerror(errno));
    std::fclose(log);
    return 1;
  }
  const lptn::fw::EstimatorConfig<double> config = make_config(o);
  lptn::fw::Estimator<double> estimator(config);
  lptn::fw::write_estimate_header(csv.get());
  lptn::fw::ReplaySinks sinks;
  lptn::fw::InputTally inputs;
  sinks.row = [&](const lptn::fw::EstimatorOutput<double>& out, TimeUs log_start_us) {
    lptn::fw::write_estimate_row(csv.get(), out, log_start_us);
    inputs.add(out);
  };
  sinks.bad_record = [&](std::size_t line, const char* why) {
    std::fprintf(stderr, "%s:%zu: %s (line skipped)\n", o.replay.c_str(), line, why);
  };
  const lptn::fw::ReplayStats s = lptn::fw::replay_candump(log, estimator, sinks);
  std::fclose(log);
  if (!csv.commit()) {
    std::fprintf(stderr, "lptn-daemon: error: writing %s failed\n", o.csv.empty() ? "stdout" : o.csv.c_str());
    return 1;
  }
  std::fprintf(stderr, "lptn-daemon: replayed %zu frames, %zu ticks, %zu estimates, %zu bad lines\n", s.frames, s.ticks,
               s.rows, s.bad_records);
  // What `lptn replay` says of the same log: each input the model did not get as the log sent it.
  for (const std::string& w : lptn::fw::input_warnings(o.replay, inputs, config))
    std::fprintf(stderr, "lptn-daemon: warning: %s\n", w.c_str());
  return 0;
}

// Frames from a candump log, handed over once the estimator's clock reaches their time (relative
// to the log's first frame), for the timer loop's --log mode.
class PacedLog {
 public:
  explicit PacedLog(std::FILE* f, const char* name) : f_(f), reader_(f), name_(name) { advance(); }
  bool done() const { return !have_; }
  TimeUs last_delivered() const { return last_; }
  template <class Deliver>
  void deliver_until(TimeUs t, Deliver&& deliver) {
    while (have_ && rec_.time_us - first_ <= t) {
      last_ = rec_.time_us - first_;
      deliver(rec_.frame, last_);
      advance();
    }
  }

 private:
  void advance() {
    have_ = false;
    if (!f_) return;
    std::string_view line;
    for (lptn::hostio::LineReader::Status status; (status = reader_.next(line)) != lptn::hostio::LineReader::Status::end;) {
      const char* why = status == lptn::hostio::LineReader::Status::too_long
                            ? "line longer than 512 bytes, not a candump line"
                            : line.empty() ? nullptr : lptn::fw::parse_candump_line(line, rec_);
      if (why) {
        std::fprintf(stderr, "%s:%zu: %s (line skipped)\n", name_, reader_.line_number(), why);
        continue;
      }
      if (line.empty()) continue;
      if (first_ < 0) first_ = rec_.time_us;
      have_ = true;
      return;
    }
  }
  std::FILE* f_;
  lptn::hostio::LineReader reader_;
  const char* name_;
  lptn::fw::CandumpRecord rec_;
  TimeUs first_ = -1, last_ = 0;
  bool have_ = false;
};

// SIGTERM and SIGINT as a readable descriptor, so the loop stops between two ticks.
int stop_signals_fd() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGINT);
  if (sigprocmask(SIG_BLOCK, &set, nullptr) != 0) return -1;
  return signalfd(-1, &set, SFD_CLOEXEC | SFD_NONBLOCK);
}

// After this many ticks of frames arriving without the estimator starting, say why on stderr (its
// status frame says it every tick; a person at the console should not have to decode it).
constexpr std::uint64_t kWarnUninitializedTicks = 100;

void warn_uninitialized(const lptn::fw::EstimatorOutput<double>& est, TimeUs dt_us) {
  std::string stale, required;
  for (int i = 0; i < lptn::fw::kNumInputs; ++i) {
    const auto b = lptn::fw::bit(static_cast<lptn::fw::Input>(i));
    if (est.stale & b) stale += std::string(stale.empty() ? "" : ", ") + lptn::fw::kInputNames[i];
    if (lptn::fw::kRequiredInputs & b) required += std::string(required.empty() ? "" : ", ") + lptn::fw::kInputNames[i];
  }
  std::fprintf(stderr,
               "lptn-daemon: warning: no estimates after %.0f s of frames: %s (the estimator starts once every "
               "required input is fresh)\n",
               static_cast<double>(kWarnUninitializedTicks * static_cast<std::uint64_t>(dt_us)) / 1e6,
               stale.empty() ? ("a required input has not arrived yet (" + required + " are required)").c_str()
                             : ("stale inputs: " + stale + " (older than their timeout at every tick)").c_str());
}

// The live loop: a monotonic timer every dt / time-scale; the estimator's clock is the monotonic
// clock since start, times the scale, so its ages and the ticks agree however fast it runs.
int run_live(const Options& o) {
  lptn::fw::CanSocket socket;
  std::FILE* log = nullptr;
  if (!o.interface.empty()) {
    std::string error;
    if (!socket.open(o.interface, lptn::bus::kFilterIds, std::size(lptn::bus::kFilterIds), error)) {
      std::fprintf(stderr, "lptn-daemon: error: %s\n", error.c_str());
      return 1;
    }
  } else if (!(log = std::fopen(o.log.c_str(), "r"))) {
    std::fprintf(stderr, "lptn-daemon: error: %s: %s\n", o.log.c_str(), std::strerror(errno));
    return 2;
  }
  lptn::hostio::AtomicFile out, record;
  if ((log && !out.open(o.out)) || (!o.record.empty() && !record.open(o.record))) {
    std::fprintf(stderr, "lptn-daemon: error: %s: %s\n", (log && !out.get() ? o.out : o.record).c_str(), std::strerror(errno));
    if (log) std::fclose(log);
    return 1;
  }
  // The record's lines are buffered (a write per 1 MiB, not per frame: the timer loop must not wait on a disk).
  static char record_buffer[1 << 20];
  if (!o.record.empty()) std::setvbuf(record.get(), record_buffer, _IOFBF, sizeof record_buffer);
  char line[160];
  const auto keep = [&](TimeUs t, const char* interface, const lptn::fw::CanFrame& f) {
    if (!o.record.empty() && lptn::fw::format_candump_line(line, sizeof line, t, interface, f))
      std::fprintf(record.get(), "%s\n", line);
  };
  const int signals = stop_signals_fd();
  const int timer = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC | TFD_NONBLOCK);
  if (signals < 0 || timer < 0) {
    std::fprintf(stderr, "lptn-daemon: error: timer or signal set-up failed: %s\n", std::strerror(errno));
    return 1;
  }
  const auto config = make_config(o);
  const TimeUs dt_us = static_cast<TimeUs>(config.observer.dt_s * kUsPerS + 0.5);
  const TimeUs period_ns = static_cast<TimeUs>(static_cast<double>(dt_us) * 1000.0 / o.time_scale);
  std::fprintf(stderr, "lptn-daemon: %s, calibration %s of %s (%s), tick %lld ms, time scale %g\n",
               log ? o.log.c_str() : o.interface.c_str(), lptn::calibration::kMethod, lptn::calibration::kMotorName,
               lptn::calibration::kCreatedUtc, static_cast<long long>(dt_us / 1000), o.time_scale);

  lptn::fw::Estimator<double> estimator(config);
  PacedLog paced = log ? PacedLog(log, o.log.c_str()) : PacedLog(nullptr, "");
  // The ticks' clock and the frames' clock share one origin: the timer is armed at `start`
  // itself (absolute), so tick k fires at start + (k + 1) period. Armed before the set-up above,
  // the ticks ran ahead of the frames' time stamps by however long the set-up took, times the
  // time scale: on a loaded machine at --time-scale 10 more than an input's timeout, which left
  // that input stale and the estimator uninitialised for the whole run.
  const TimeUs start = monotonic_us();
  itimerspec spec{};
  spec.it_interval.tv_sec = static_cast<time_t>(period_ns / 1000000000);
  spec.it_interval.tv_nsec = static_cast<long>(period_ns % 1000000000);
  const TimeUs first_ns = start * 1000 + period_ns;
  spec.it_value.tv_sec = static_cast<time_t>(first_ns / 1000000000);
  spec.it_value.tv_nsec = static_cast<long>(first_ns % 1000000000);
  if (timerfd_settime(timer, TFD_TIMER_ABSTIME, &spec, nullptr) != 0) {
    std::fprintf(stderr, "lptn-daemon: error: timer set-up failed: %s\n", std::strerror(errno));
    return 1;
  }
  auto now = [&] { return static_cast<TimeUs>(static_cast<double>(monotonic_us() - start) * o.time_scale); };
  const TimeUs stop_at = o.duration_s > 0 ? static_cast<TimeUs>(o.duration_s * kUsPerS) : -1;
  // Tick k stands for the time the timer fired, (k + 1) dt after start; a log's ticks start at its
  // first frame instead, as a replay's do.
  TimeUs tick_time = log ? -dt_us : 0;
  std::uint64_t ticks = 0, frames_in = 0, frames_out = 0;
  // Ticks without estimates: all of them before the first frame; with frames arriving, a warning
  // once they last (the converter's frames are there, yet an input stays stale or absent).
  std::uint64_t uninitialized_ticks = 0, waiting_with_frames = 0;
  lptn::fw::CanFrame outputs[lptn::fw::kMaxOutputFrames];
  int rc = 0;
  // A socket error the run goes on after (a link down): said, and the socket read on.
  const auto reading_on = [&](int error) {
    std::fprintf(stderr, "lptn-daemon: warning: %s: %s; reading on\n", o.interface.c_str(), std::strerror(error));
  };
  for (bool running = true; running;) {
    pollfd fds[3] = {{signals, POLLIN, 0}, {timer, POLLIN, 0}, {socket.fd(), POLLIN, 0}};
    if (poll(fds, log ? 2 : 3, -1) < 0 && errno != EINTR) {
      rc = 1;
      break;
    }
    if (fds[0].revents & POLLIN) break;  // SIGTERM or SIGINT: stop between ticks
    if (!log && (fds[2].revents & (POLLERR | POLLHUP | POLLNVAL))) {
      // A pending socket error makes poll() return at once until it is taken: left there, the loop
      // spun a core and said nothing while the interface was gone. The interface removed (ENODEV;
      // a USB adapter unplugged, a driver reset) ends the run: no frame can come or go on this
      // socket. The record and the outputs so far are committed, as on SIGTERM: they are what
      // led up to it. Any other error (a link down, ENETDOWN) is said and cleared, and the socket
      // reads on once the link is up again.
      const int error = socket.take_error();
      const bool gone = (fds[2].revents & (POLLHUP | POLLNVAL)) || error == ENODEV ||
                        (error == 0 && !(fds[2].revents & POLLIN));
      if (gone) {
        std::fprintf(stderr, "lptn-daemon: error: %s: %s; stopped, what was received until then is kept\n",
                     o.interface.c_str(), error ? std::strerror(error) : "the socket reports a failure");
        rc = 1;
        break;
      }
      if (error) reading_on(error);
    }
    if (!log && (fds[2].revents & POLLIN)) {
      lptn::fw::CanFrame f;
      bool overrun = false;
      for (lptn::fw::CanSocket::Read r; (r = socket.read(f, overrun)) != lptn::fw::CanSocket::Read::none;) {
        if (r == lptn::fw::CanSocket::Read::failed) {
          const int error = errno;
          if (error == ENETDOWN) {  // the pending error of a link that went down, returned by the read
            reading_on(error);
            break;
          }
          // Stopped as on SIGTERM (not returned from here: the record would be thrown away).
          std::fprintf(stderr, "lptn-daemon: error: reading %s: %s; stopped, what was received until then is kept\n",
                       o.interface.c_str(), std::strerror(error));
          rc = 1;
          running = false;
          break;
        }
        const TimeUs t = now();
        if (overrun) {
          estimator.note_overrun();
          keep(t, "overrun", lptn::fw::CanFrame{});  // the kernel dropped frames before this one
        }
        estimator.receive(f, t);
        keep(t, "rx", f);
        ++frames_in;
      }
      if (!running) break;
    }
    if (!(fds[1].revents & POLLIN)) continue;
    std::uint64_t expirations = 0;
    if (::read(timer, &expirations, sizeof expirations) != sizeof expirations) continue;
    // A late wake-up runs the missed ticks, so the estimator's time stays dt per tick.
    for (std::uint64_t k = 0; k < expirations && running; ++k) {
      tick_time += dt_us;
      if (log) {
        paced.deliver_until(tick_time, [&](const lptn::fw::CanFrame& f, TimeUs t) {
          estimator.receive(f, t);
          keep(t, "rx", f);
          ++frames_in;
        });
        // The log has ended: no tick beyond its last frame (where a replay stops too).
        if (paced.done() && tick_time > paced.last_delivered()) {
          running = false;
          break;
        }
      }
      const lptn::fw::EstimatorOutput<double>& est = estimator.tick(tick_time);
      ++ticks;
      if (est.mode == lptn::fw::Mode::not_initialized) {
        ++uninitialized_ticks;
        if (frames_in > 0 && ++waiting_with_frames == kWarnUninitializedTicks) warn_uninitialized(est, dt_us);
      }
      const int n = lptn::fw::pack_outputs(est, outputs);
      for (int i = 0; i < n; ++i) {
        keep(tick_time, "tx", outputs[i]);
        if (log) {
          if (lptn::fw::format_candump_line(line, sizeof line, tick_time, "lptn", outputs[i]))
            std::fprintf(out.get(), "%s\n", line);
        } else if (!socket.write(outputs[i])) {
          continue;  // a full transmit queue drops this tick's frame; the next tick sends anew
        }
        ++frames_out;
      }
      if (stop_at >= 0 && tick_time >= stop_at) running = false;
    }
  }
  if (log) {
    std::fclose(log);
    if (!out.commit()) rc = 1;
  }
  if (!o.record.empty() && !record.commit()) {
    std::fprintf(stderr, "lptn-daemon: error: writing %s: %s\n", o.record.c_str(), std::strerror(errno));
    rc = 1;
  }
  std::fprintf(stderr, "lptn-daemon: stopped after %llu ticks (%llu without estimates), %llu frames in, %llu frames out\n",
               static_cast<unsigned long long>(ticks), static_cast<unsigned long long>(uninitialized_ticks),
               static_cast<unsigned long long>(frames_in), static_cast<unsigned long long>(frames_out));
  return rc;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (const int rc = parse_options(argc, argv, o)) return rc < 0 ? 0 : rc;
  if (!o.replay.empty()) return run_replay(o);
  return run_live(o);
}
