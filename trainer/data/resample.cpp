// Per-channel sample lists -> fixed grid, with the gap policy of each channel applied and
// reported.

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "trainer/data/dataset.hpp"
#include "trainer/data/internal/raw_cycle.hpp"
#include "trainer/data/internal/text.hpp"

namespace lptn::data::internal {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// How far a grid time may sit from a sample time and still count as on it: t0 + k*dt is not
// exact in binary, and epoch-sized time stamps lose more to rounding than small ones.
double time_tolerance(double dt, double t_abs_max) { return 1e-6 * dt + 1e-15 * t_abs_max; }

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2 == 1) return *mid;
  const double upper = *mid;
  const double lower = *std::max_element(v.begin(), mid);
  return 0.5 * (lower + upper);
}

std::string cname(Channel c) { return std::string(channel_name(c)); }

}  // namespace

Series merge_duplicates(const RawCycle& raw, Channel c) {
  const RawChannel& ch = raw.channels[index_of(c)];
  Series s;
  s.t.reserve(ch.rows.size());
  s.v.reserve(ch.rows.size());
  s.first_line.reserve(ch.rows.size());
  s.last_line.reserve(ch.rows.size());
  std::size_t group = 0;  // samples merged into s.v.back() so far
  bool group_conflicts = false;
  for (std::size_t i = 0; i < ch.rows.size(); ++i) {
    const double t = raw.time[ch.rows[i]];
    const std::uint32_t line = raw.line[ch.rows[i]];
    if (!s.t.empty() && t == s.t.back()) {
      if (group == 1) ++s.repeated;
      const double first = ch.values[i - group];
      if (!group_conflicts && ch.values[i] != first) {
        group_conflicts = true;
        if (s.conflicting++ == 0) {
          s.conflict_t = t;
          s.conflict_a = first;
          s.conflict_b = ch.values[i];
          s.conflict_line_a = s.first_line.back();
          s.conflict_line_b = line;
        }
      }
      // Running mean rather than sum/count so the common no-duplicate case needs no second pass.
      ++group;
      s.v.back() += (ch.values[i] - s.v.back()) / static_cast<double>(group);
      s.last_line.back() = line;
    } else {
      group = 1;
      group_conflicts = false;
      s.t.push_back(t);
      s.v.push_back(ch.values[i]);
      s.first_line.push_back(line);
      s.last_line.push_back(line);
    }
  }
  return s;
}

void resample(const Series& s, double t0, double dt, std::size_t steps, double max_gap_s, float* out) {
  const std::size_t m = s.t.size();
  if (m == 0) {
    std::fill(out, out + steps, kNaN);
    return;
  }
  const double tol = time_tolerance(dt, std::max({std::fabs(t0), std::fabs(s.t.front()), std::fabs(s.t.back())}));
  std::size_t j = 0;
  for (std::size_t k = 0; k < steps; ++k) {
    const double t = t0 + static_cast<double>(k) * dt;
    while (j + 1 < m && s.t[j + 1] <= t + tol) ++j;
    if (s.t[j] > t + tol) {
      out[k] = kNaN;  // before the first sample
    } else if (std::fabs(t - s.t[j]) <= tol) {
      out[k] = static_cast<float>(s.v[j]);
    } else if (j + 1 >= m) {
      out[k] = kNaN;  // after the last sample
    } else {
      const double span = s.t[j + 1] - s.t[j];
      if (span > max_gap_s) {
        out[k] = kNaN;
      } else {
        const double a = (t - s.t[j]) / span;
        out[k] = static_cast<float>(s.v[j] + a * (s.v[j + 1] - s.v[j]));
      }
    }
  }
}

Dataset assemble(RawCycle&& raw, const LoadOptions& options) {
  const std::string where = raw.file.string();
  const double dt = options.dt_s;
  const double t0 = raw.time.front();
  const double t_end = raw.time.back();
  const double tol = time_tolerance(dt, std::max(std::fabs(t0), std::fabs(t_end)));

  CycleReport rep;
  rep.name = raw.name.empty() ? raw.file.stem().string() : raw.name;
  rep.file = raw.file;
  rep.duration_s = t_end - t0;
  rep.rows = raw.time.size();
  rep.findings = std::move(raw.findings);
  const auto warn = [&](std::string msg) { rep.findings.push_back({Finding::Severity::warning, std::move(msg)}); };
  const auto note = [&](std::string msg) { rep.findings.push_back({Finding::Severity::info, std::move(msg)}); };

  const double grid_points = std::floor((t_end - t0 + tol) / dt) + 1.0;
  if (!(grid_points <= static_cast<double>(options.max_grid_points))) {
    throw DataError(strf("%s:%u: column 'time_s': %s s after the first row at dt %s s makes %.0f grid points "
                         "(limit %zu); is the time column in seconds?",
                         where.c_str(), static_cast<unsigned>(raw.line.back()), num(t_end - t0).c_str(),
                         num(dt).c_str(), grid_points, options.max_grid_points));
  }
  const auto steps = static_cast<std::size_t>(grid_points);

  std::array<std::vector<float>, kNumChannels> grid;
  struct LongGap {
    Channel channel;
    Gap gap;
    double limit_s;
  };
  std::vector<LongGap> long_gaps;  // longer than the channel's bridging limit, warned about below
  // First and last sample time of each split channel, to explain a trimmed cycle.
  std::array<std::pair<double, std::uint32_t>, kNumChannels> first_sample{}, last_sample{};

  for (Channel c : kAllChannels) {
    const std::size_t i = index_of(c);
    const ChannelInfo& info = channel_info(c);
    ChannelReport& cr = rep.channels[i];
    cr.channel = c;
    cr.present = raw.channels[i].present;
    cr.samples = raw.channels[i].values.size();
    if (!cr.present) continue;

    const Series s = merge_duplicates(raw, c);
    raw.channels[i] = RawChannel{true, {}, {}};  // the grid copy replaces it; keep the peak down
    // The contract lets time stamps repeat (rows need only be non-decreasing), so readings of one
    // instant are averaged; readings that disagree usually mean a logger fault, so they are named.
    if (s.conflicting > 0) {
      warn(strf("%s: column '%s': %zu time stamps carry differing readings, each averaged; the first at t=%s s: %s on "
                "line %u, %s on line %u (two readings of one instant: a logger fault?)",
                where.c_str(), cname(c).c_str(), s.conflicting, num(s.conflict_t).c_str(), num(s.conflict_a).c_str(),
                static_cast<unsigned>(s.conflict_line_a), num(s.conflict_b).c_str(),
                static_cast<unsigned>(s.conflict_line_b)));
    } else if (s.repeated > 0) {
      rep.findings.push_back({Finding::Severity::info,
                              strf("%s: column '%s': %zu time stamps repeated with the same reading; merged", where.c_str(),
                                   cname(c).c_str(), s.repeated)});
    }
    if (s.t.empty()) {
      grid[i].assign(steps, kNaN);
      continue;
    }
    first_sample[i] = {s.t.front(), s.first_line.front()};
    last_sample[i] = {s.t.back(), s.last_line.back()};

    std::vector<double> intervals(s.t.size() - 1);
    for (std::size_t j = 0; j + 1 < s.t.size(); ++j) intervals[j] = s.t[j + 1] - s.t[j];
    const double typical = median(intervals);
    cr.native_rate_hz = typical > 0 ? 1.0 / typical : 0.0;

    const double max_gap = options.max_gap_s[i];
    const bool split = info.on_long_gap == GapPolicy::split;
    if (typical > max_gap) {
      warn(strf("%s: column '%s': logged every %s s, longer than its %s s bridging limit, so most of it is %s; "
                "raise the limit for this channel",
                where.c_str(), cname(c).c_str(), num(typical).c_str(), num(max_gap).c_str(),
                split ? "split away" : "masked"));
    }
    for (std::size_t j = 0; j < intervals.size(); ++j) {
      const double d = intervals[j];
      const bool too_long = d > max_gap;
      if (!too_long && !(d > 3.0 * typical)) continue;
      const Gap::Action action = !too_long ? Gap::Action::bridged : split ? Gap::Action::split : Gap::Action::masked;
      cr.gaps.push_back({s.t[j], s.t[j + 1], s.last_line[j], s.first_line[j + 1], action});
      if (too_long) long_gaps.push_back({c, cr.gaps.back(), max_gap});
    }

    grid[i].resize(steps);
    resample(s, t0, dt, steps, max_gap, grid[i].data());
    const auto valid = std::count_if(grid[i].begin(), grid[i].end(), [](float v) { return !std::isnan(v); });
    cr.coverage = static_cast<double>(valid) / static_cast<double>(steps);
  }

  // One warning per dropout, naming every column it hit: an export's dropout hits them all at once.
  std::sort(long_gaps.begin(), long_gaps.end(),
            [](const LongGap& a, const LongGap& b) { return a.gap.start_s < b.gap.start_s; });
  std::vector<bool> told(long_gaps.size(), false);
  for (std::size_t a = 0; a < long_gaps.size(); ++a) {
    if (told[a]) continue;
    const Gap& g = long_gaps[a].gap;
    std::vector<std::size_t> group{a};
    for (std::size_t b = a + 1; b < long_gaps.size(); ++b) {
      const Gap& h = long_gaps[b].gap;
      if (!told[b] && h.start_s < g.end_s && h.end_s > g.start_s) group.push_back(b);
    }
    std::sort(group.begin(), group.end(), [&](std::size_t x, std::size_t y) {
      return index_of(long_gaps[x].channel) < index_of(long_gaps[y].channel);
    });
    bool any_split = false;
    std::string columns;
    for (std::size_t i : group) {
      told[i] = true;
      any_split = any_split || long_gaps[i].gap.action == Gap::Action::split;
      columns += (columns.empty() ? "'" : ", '") + cname(long_gaps[i].channel) + "'";
    }
    if (group.size() == 1) {
      warn(strf("%s: column %s: no sample for %s s, from t=%s s (line %u) to t=%s s (line %u), longer than "
                "the %s s bridging limit; %s",
                where.c_str(), columns.c_str(), num(g.end_s - g.start_s).c_str(), num(g.start_s).c_str(),
                static_cast<unsigned>(g.line_before), num(g.end_s).c_str(), static_cast<unsigned>(g.line_after),
                num(long_gaps[a].limit_s).c_str(), any_split ? "cycle split there" : "masked there"));
    } else {
      warn(strf("%s: columns %s: no sample for %s s, from t=%s s (line %u) to t=%s s (line %u), longer than "
                "their bridging limits; %s",
                where.c_str(), columns.c_str(), num(g.end_s - g.start_s).c_str(), num(g.start_s).c_str(),
                static_cast<unsigned>(g.line_before), num(g.end_s).c_str(), static_cast<unsigned>(g.line_after),
                any_split ? "cycle split there" : "masked there"));
    }
  }

  // The simulation needs every split channel at every step, so segments are the runs where all
  // of them are valid.
  std::vector<std::size_t> drivers;
  for (Channel c : kAllChannels) {
    if (channel_info(c).on_long_gap == GapPolicy::split && !grid[index_of(c)].empty()) drivers.push_back(index_of(c));
  }
  const auto drivable = [&](std::size_t k) {
    return std::all_of(drivers.begin(), drivers.end(), [&](std::size_t i) { return !std::isnan(grid[i][k]); });
  };
  std::vector<std::pair<std::size_t, std::size_t>> runs;  // [begin, end) grid indices
  for (std::size_t k = 0; k < steps;) {
    while (k < steps && !drivable(k)) ++k;
    const std::size_t begin = k;
    while (k < steps && drivable(k)) ++k;
    if (k > begin) runs.emplace_back(begin, k);
  }

  if (!drivers.empty()) {
    const auto late = *std::max_element(drivers.begin(), drivers.end(), [&](std::size_t a, std::size_t b) {
      return first_sample[a].first < first_sample[b].first;
    });
    if (first_sample[late].first > t0 + tol) {
      note(strf("%s: column '%s': first sample at t=%s s (line %u); the %s s before it are left out", where.c_str(),
                cname(kAllChannels[late]).c_str(), num(first_sample[late].first).c_str(),
                static_cast<unsigned>(first_sample[late].second), num(first_sample[late].first - t0).c_str()));
    }
    const auto early = *std::min_element(drivers.begin(), drivers.end(), [&](std::size_t a, std::size_t b) {
      return last_sample[a].first < last_sample[b].first;
    });
    if (last_sample[early].first < t_end - tol) {
      note(strf("%s: column '%s': last sample at t=%s s (line %u); the %s s after it are left out", where.c_str(),
                cname(kAllChannels[early]).c_str(), num(last_sample[early].first).c_str(),
                static_cast<unsigned>(last_sample[early].second), num(t_end - last_sample[early].first).c_str()));
    }
  }

  std::vector<std::pair<std::size_t, std::size_t>> kept;
  for (const auto& [begin, end] : runs) {
    const double length = static_cast<double>(end - begin - 1) * dt;
    if (runs.size() > 1 && length < options.min_segment_s) {
      warn(strf("%s: segment t=%s..%s s (%s s) is shorter than %s s after the split; dropped", where.c_str(),
                num(t0 + static_cast<double>(begin) * dt).c_str(), num(t0 + static_cast<double>(end - 1) * dt).c_str(),
                num(length).c_str(), num(options.min_segment_s).c_str()));
    } else {
      kept.emplace_back(begin, end);
    }
  }
  if (kept.empty()) {
    warn(strf("%s: %s; the file contributes no cycle", where.c_str(),
              runs.empty() ? "no time at which speed, current, frequency, airflow and ambient all have data"
                           : "no segment long enough"));
  }

  Dataset out;
  for (std::size_t n = 0; n < kept.size(); ++n) {
    const auto [begin, end] = kept[n];
    Cycle cycle;
    cycle.name = n == 0 ? rep.name : rep.name + "-" + std::to_string(n + 1);  // shell-safe, unlike "#"
    cycle.file = raw.file;
    cycle.t0_s = t0 + static_cast<double>(begin) * dt;
    cycle.dt_s = dt;
    cycle.steps = end - begin;
    for (std::size_t i = 0; i < grid.size(); ++i) {
      if (grid[i].empty()) continue;
      if (begin == 0 && end == steps) {
        cycle.samples[i] = std::move(grid[i]);  // the common unsplit case: no copy
      } else {
        cycle.samples[i].assign(grid[i].begin() + static_cast<std::ptrdiff_t>(begin),
                                grid[i].begin() + static_cast<std::ptrdiff_t>(end));
      }
    }
    out.cycles.push_back(std::move(cycle));
  }
  out.reports.push_back(std::move(rep));
  return out;
}

}  // namespace lptn::data::internal
