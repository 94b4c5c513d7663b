// The `lptn inspect` report and the nameplate plausibility check.

#include "trainer/data/inspection.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "trainer/data/internal/text.hpp"

namespace lptn::data {
namespace {

using internal::num;
using internal::strf;

const char* action_name(Gap::Action a) {
  switch (a) {
    case Gap::Action::bridged: return "bridged";
    case Gap::Action::masked: return "masked";
    case Gap::Action::split: return "split";
  }
  return "?";
}

const char* severity_name(Finding::Severity s) { return s == Finding::Severity::warning ? "warning" : "info"; }

double total_hours(const Dataset& d) {
  double s = 0;
  for (const Cycle& c : d.cycles) s += c.duration_s();
  return s / 3600.0;
}

std::vector<const Cycle*> segments_of(const Dataset& d, const CycleReport& r) {
  std::vector<const Cycle*> out;
  for (const Cycle& c : d.cycles) {
    // A file a data map cut into drives has a report per drive: its own name, or that name with a
    // gap's segment number ("-2") after it.
    const bool segment = c.name.size() > r.name.size() + 1 && c.name.compare(0, r.name.size(), r.name) == 0 &&
                         c.name[r.name.size()] == '-' &&
                         std::all_of(c.name.begin() + static_cast<std::ptrdiff_t>(r.name.size()) + 1, c.name.end(),
                                     [](char ch) { return ch >= '0' && ch <= '9'; });
    if (c.file == r.file && (c.name == r.name || segment)) out.push_back(&c);
  }
  return out;
}

}  // namespace

std::string format_report(const Dataset& dataset) {
  std::string out;
  for (const CycleReport& r : dataset.reports) {
    out += strf("%s  (%s)\n", r.name.c_str(), r.file.string().c_str());
    out += strf("  duration %s s (%.2f h), %zu rows\n", num(r.duration_s).c_str(), r.duration_s / 3600.0, r.rows);
    out += strf("  %-18s %10s %10s %9s %5s\n", "channel", "rate Hz", "samples", "coverage", "gaps");
    for (const ChannelReport& c : r.channels) {
      const std::string name(channel_name(c.channel));
      if (!c.present) {
        out += strf("  %-18s %10s\n", name.c_str(), "absent");
        continue;
      }
      out += strf("  %-18s %10.3f %10zu %8.1f%% %5zu\n", name.c_str(), c.native_rate_hz, c.samples,
                  100.0 * c.coverage, c.gaps.size());
    }
    bool any_gap = false;
    for (const ChannelReport& c : r.channels) any_gap = any_gap || !c.gaps.empty();
    if (any_gap) {
      out += "  gaps:\n";
      for (const ChannelReport& c : r.channels) {
        for (const Gap& g : c.gaps) {
          out += strf("    %-18s at %s s for %s s (lines %zu..%zu): %s\n",
                      std::string(channel_name(c.channel)).c_str(), num(g.start_s).c_str(),
                      num(g.end_s - g.start_s).c_str(), g.line_before, g.line_after, action_name(g.action));
        }
      }
    }
    if (!r.findings.empty()) {
      out += "  findings:\n";
      for (const Finding& f : r.findings) out += strf("    %s: %s\n", severity_name(f.severity), f.message.c_str());
    }
    const auto segments = segments_of(dataset, r);
    out += "  cycles:";
    if (segments.empty()) out += " none";
    for (const Cycle* c : segments) {
      out += strf(" %s (t=%s..%s s)", c->name.c_str(), num(c->t0_s).c_str(), num(c->t0_s + c->duration_s()).c_str());
    }
    out += "\n\n";
  }
  out += strf("%zu cycles, %.2f h of data, %zu warnings\n", dataset.cycles.size(), total_hours(dataset),
              dataset.warning_count());
  return out;
}

nlohmann::json report_json(const Dataset& dataset) {
  nlohmann::json cycles = nlohmann::json::array();
  for (const CycleReport& r : dataset.reports) {
    nlohmann::json channels = nlohmann::json::object();
    for (const ChannelReport& c : r.channels) {
      nlohmann::json gaps = nlohmann::json::array();
      for (const Gap& g : c.gaps) {
        gaps.push_back({{"start_s", g.start_s},
                        {"end_s", g.end_s},
                        {"line_before", g.line_before},
                        {"line_after", g.line_after},
                        {"action", action_name(g.action)}});
      }
      channels[std::string(channel_name(c.channel))] = {{"present", c.present},
                                                         {"native_rate_hz", c.native_rate_hz},
                                                         {"samples", c.samples},
                                                         {"coverage", c.coverage},
                                                         {"gaps", std::move(gaps)}};
    }
    nlohmann::json findings = nlohmann::json::array();
    for (const Finding& f : r.findings) findings.push_back({{"severity", severity_name(f.severity)}, {"message", f.message}});
    nlohmann::json segments = nlohmann::json::array();
    for (const Cycle* c : segments_of(dataset, r)) {
      segments.push_back({{"name", c->name}, {"start_s", c->t0_s}, {"duration_s", c->duration_s()}, {"steps", c->steps}});
    }
    cycles.push_back({{"name", r.name},
                      {"file", r.file.string()},
                      {"duration_s", r.duration_s},
                      {"rows", r.rows},
                      {"channels", std::move(channels)},
                      {"findings", std::move(findings)},
                      {"segments", std::move(segments)}});
  }
  return {{"cycles", std::move(cycles)},
          {"cycle_count", dataset.cycles.size()},
          {"hours", total_hours(dataset)},
          {"warnings", dataset.warning_count()}};
}

namespace {
constexpr double kCurrentFactor = 4.0;
constexpr double kVoltageFactor = 1.3;
// Slip of a traction induction motor is a few Hz at most; more means wrong pole pairs or scaling.
constexpr double kFrequencyTolerance = 10.0;
constexpr double kFrequencyShare = 0.01;
}  // namespace

NameplateCheck::NameplateCheck(const Nameplate& np) : nameplate_(np) {
  if (np.pole_pairs <= 0 || !(np.rated_current_a > 0) || !(np.rated_voltage_v > 0)) {
    throw std::invalid_argument("check_against_nameplate: pole_pairs, rated current and rated voltage must be positive");
  }
}

void NameplateCheck::Over::add(float v, double limit) {
  if (std::isnan(v)) return;
  ++valid;
  if (v > limit) ++over;
  peak = std::max(peak, static_cast<double>(v));
}

void NameplateCheck::add(float speed_rpm, float current_a, float frequency_hz, float voltage_v) {
  current_.add(current_a, kCurrentFactor * nameplate_.rated_current_a);
  voltage_.add(voltage_v, kVoltageFactor * nameplate_.rated_voltage_v);
  if (std::isnan(speed_rpm) || std::isnan(frequency_hz)) return;
  ++both_;
  // Magnitudes: some drives log the frequency unsigned while the speed carries the direction.
  const double expected = std::fabs(static_cast<double>(speed_rpm)) * nameplate_.pole_pairs / 60.0;
  if (std::fabs(std::fabs(static_cast<double>(frequency_hz)) - expected) > kFrequencyTolerance) ++off_;
}

std::vector<Finding> NameplateCheck::findings(const std::string& who) const {
  std::vector<Finding> out;
  const auto over = [&](const Over& o, Channel ch, const char* what, double rated, const char* unit) {
    if (o.over == 0) return;
    out.push_back({Finding::Severity::warning,
                   strf("%s: %s above %s rated (%s %s) at %zu of %zu steps (%.2f%%), peak %s %s", who.c_str(),
                        std::string(channel_name(ch)).c_str(), what, num(rated).c_str(), unit, o.over, o.valid,
                        100.0 * static_cast<double>(o.over) / static_cast<double>(o.valid), num(o.peak).c_str(), unit)});
  };
  over(current_, Channel::current_a, "4x", nameplate_.rated_current_a, "A");
  over(voltage_, Channel::voltage_v, "1.3x", nameplate_.rated_voltage_v, "V");
  if (both_ > 0 && static_cast<double>(off_) > kFrequencyShare * static_cast<double>(both_)) {
    out.push_back({Finding::Severity::warning,
                   strf("%s: frequency_hz differs from speed_rpm * %d / 60 by more than %s Hz at %zu of %zu steps "
                        "(%.1f%%); check pole_pairs and the channels' scaling",
                        who.c_str(), nameplate_.pole_pairs, num(kFrequencyTolerance).c_str(), off_, both_,
                        100.0 * static_cast<double>(off_) / static_cast<double>(both_))});
  }
  return out;
}

std::vector<Finding> check_against_nameplate(const Dataset& dataset, const Nameplate& np) {
  const NameplateCheck empty(np);  // checks the nameplate before any cycle
  std::vector<Finding> out;
  for (const Cycle& c : dataset.cycles) {
    NameplateCheck check = empty;
    for (std::size_t k = 0; k < c.steps; ++k)
      check.add(c.at(Channel::speed_rpm, k), c.at(Channel::current_a, k), c.at(Channel::frequency_hz, k),
                c.at(Channel::voltage_v, k));
    for (Finding& f : check.findings(strf("cycle %s (%s)", c.name.c_str(), c.file.string().c_str())))
      out.push_back(std::move(f));
  }
  return out;
}

std::vector<std::string> inspection_warnings(const Dataset& dataset) {
  std::vector<std::string> out;
  for (const CycleReport& r : dataset.reports) {
    for (const Finding& f : r.findings)
      if (f.severity == Finding::Severity::warning) out.push_back(f.message);
  }
  return out;
}

std::vector<std::string> inspection_warnings(const Dataset& dataset, const Nameplate& nameplate) {
  std::vector<std::string> out = inspection_warnings(dataset);
  for (const Finding& f : check_against_nameplate(dataset, nameplate))
    if (f.severity == Finding::Severity::warning) out.push_back(f.message);
  return out;
}

}  // namespace lptn::data
