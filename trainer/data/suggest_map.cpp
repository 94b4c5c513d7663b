// lptn inspect --suggest-map: a data map proposed from an export's header and values.

#include "trainer/data/suggest_map.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "hostio/utf8.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/data/internal/csv.hpp"
#include "trainer/data/internal/text.hpp"

namespace lptn::data {
namespace {

using internal::CellSplitter;
using internal::LineSplitter;
using internal::NumberStatus;
using internal::strf;
using internal::is_comment;
using internal::trim;
using internal::unquoted;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::size_t kSampleRows = 100'000;  // rows whose values are looked at (times: every row)

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

bool contains_any(const std::string& name, std::initializer_list<std::string_view> words) {
  return std::any_of(words.begin(), words.end(), [&](std::string_view w) { return name.find(w) != std::string::npos; });
}

bool starts_with_any(const std::string& name, std::initializer_list<std::string_view> words) {
  return std::any_of(words.begin(), words.end(), [&](std::string_view w) { return name.rfind(w, 0) == 0; });
}

// Texts exports write for "no value".
constexpr std::string_view kMissingTokens[] = {"NaN", "nan", "NAN", "NA", "N/A", "n/a", "#N/A", "-", "--", "null",
                                               "NULL", "None", "none", "?"};

bool is_missing_token(std::string_view s) {
  return std::find(std::begin(kMissingTokens), std::end(kMissingTokens), s) != std::end(kMissingTokens);
}

struct Column {
  std::string name, key;  // as written; lower case
  std::vector<double> values;  // per sampled row; NaN where empty or not a number
  std::size_t numbers = 0, texts = 0, iso = 0;
  std::map<std::string, std::size_t> text_counts;  // the non-numeric texts seen (bounded)
  double q05 = kNaN, q25 = kNaN, median = kNaN, q75 = kNaN, q95 = kNaN, min = kNaN, max = kNaN;
  double negative_share = 0;  // of its numbers
  double roughness = 0;  // median |step| between consecutive numbers over (q95 - q05): small for temperatures
  std::size_t changes = 0;  // rows whose text differs from the row before
  bool taken = false;
};

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return kNaN;
  const auto at = v.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), at, v.end());
  return *at;
}

void summarize(Column& c) {
  std::vector<double> v;
  for (double x : c.values)
    if (!std::isnan(x)) v.push_back(x);
  if (v.empty()) return;
  c.q05 = quantile(v, 0.05);
  c.q25 = quantile(v, 0.25);
  c.median = quantile(v, 0.5);
  c.q75 = quantile(v, 0.75);
  c.q95 = quantile(v, 0.95);
  c.min = *std::min_element(v.begin(), v.end());
  c.max = *std::max_element(v.begin(), v.end());
  c.negative_share = static_cast<double>(std::count_if(v.begin(), v.end(), [](double x) { return x < 0; })) /
                     static_cast<double>(v.size());
  std::vector<double> steps;
  for (std::size_t i = 1; i < v.size(); ++i) steps.push_back(std::fabs(v[i] - v[i - 1]));
  const double spread = c.q95 - c.q05;
  c.roughness = steps.empty() || !(spread > 0) ? 0.0 : quantile(steps, 0.5) / spread;
}

// The separator that splits the header and (nearly) every row into the same number of cells.
char detect_separator(const std::vector<std::string_view>& lines) {
  char best = ',';
  std::size_t best_cells = 0;
  for (const char sep : {',', ';', '\t', '|'}) {
    const std::size_t cells = internal::count_cells(lines.front(), sep);
    if (cells < 2) continue;
    const auto same = std::count_if(lines.begin(), lines.end(),
                                    [&](std::string_view l) { return internal::count_cells(l, sep) == cells; });
    if (static_cast<double>(same) < 0.95 * static_cast<double>(lines.size())) continue;
    if (cells > best_cells) {
      best = sep;
      best_cells = cells;
    }
  }
  return best;
}

bool digit(char c) { return c >= '0' && c <= '9'; }

// "12,5" against "12.5": which of the two a file's numbers are written with.
char detect_decimal(const std::vector<std::string_view>& rows, char sep) {
  if (sep == ',') return '.';
  std::size_t comma = 0, point = 0;
  for (std::string_view row : rows) {
    CellSplitter cells(row, sep);
    std::string_view cell;
    while (cells.next(cell)) {
      cell = unquoted(cell);
      const std::size_t c = cell.find(','), p = cell.find('.');
      if (c != std::string_view::npos && c > 0 && c + 1 < cell.size() && digit(cell[c - 1]) && digit(cell[c + 1])) ++comma;
      if (p != std::string_view::npos && p > 0 && p + 1 < cell.size() && digit(cell[p - 1]) && digit(cell[p + 1])) ++point;
    }
  }
  return comma > point ? ',' : '.';
}

struct Choice {
  Channel channel;
  std::size_t column;
  std::string unit;
  std::string why;
};

// How strongly a column's name says it is channel c: 3 lptn's own name, 2 a word for it, 1 the
// engineering letter convention (n_ speed, M_ torque, I_ current, U_ voltage, f_ frequency,
// Q_ flow), 0 nothing.
int name_score(Channel c, const std::string& key) {
  if (key == channel_name(c)) return 3;
  const bool vehicle = contains_any(key, {"vehicle", "train", "wheel", "kmh", "km/h", "fahrzeug", "zug", "gps"});
  // "T_Luft", "air temp [°C]": a temperature of the air, not its flow.
  const bool temperature = starts_with_any(key, {"t_", "t ", "t[", "temp"}) ||
                           contains_any(key, {"temp", "°c", "degc", "°f", "degf", "kelvin", "[k]", "(k)"});
  switch (c) {
    case Channel::speed_rpm:
      if (vehicle) return 0;
      if (contains_any(key, {"speed", "rpm", "drehzahl", "n_mot", "nmot", "motor_n", "1/min"})) return 2;
      return starts_with_any(key, {"n_", "n ", "n["}) ? 1 : 0;
    case Channel::frequency_hz:
      if (contains_any(key, {"freq", "frequenz", "f_stator", "stator_f", "f_out", "f_mot", "fstator"})) return 2;
      return starts_with_any(key, {"f_", "f ", "f["}) ? 1 : 0;
    case Channel::current_a:
      if (contains_any(key, {"current", "strom", "i_phase", "iphase", "i_mot", "irms", "i_rms", "amps"})) return 2;
      return starts_with_any(key, {"i_", "i ", "i["}) ? 1 : 0;
    case Channel::torque_nm:
      if (contains_any(key, {"torque", "moment", "trq", "m_mot", "m_motor"})) return 2;
      return starts_with_any(key, {"m_", "m ", "m["}) ? 1 : 0;
    case Channel::voltage_v:
      if (contains_any(key, {"volt", "spannung", "u_zk", "uzk", "udc", "u_dc", "vdc", "v_dc", "dclink", "dc_link"})) return 2;
      return starts_with_any(key, {"u_", "u ", "u[", "v_"}) ? 1 : 0;
    case Channel::airflow_m3s:
      if (temperature) return 0;
      if (contains_any(key, {"airflow", "air_flow", "luft", "volumenstrom", "blower", "cooling_air", "flow"})) return 2;
      return starts_with_any(key, {"q_", "q ", "q["}) ? 1 : 0;
    case Channel::ambient_c:
      if (contains_any(key, {"ambient", "umgebung", "outside", "outdoor", "aussen", "außen", "inlet", "amb"})) return 2;
      return temperature && contains_any(key, {"luft", "air"}) ? 2 : 0;
    case Channel::stator_winding_c:
      if (contains_any(key, {"stator", "winding", "wicklung", "stw"})) return 2;
      return 0;
    case Channel::rotor_c:
      if (contains_any(key, {"rotor", "laeufer", "läufer"})) return 2;
      return 0;
  }
  return 0;
}

bool is_temperature_channel(Channel c) {
  return c == Channel::ambient_c || c == Channel::stator_winding_c || c == Channel::rotor_c;
}

// The unit a temperature column is in: by its name if it says, else by its values; empty when
// neither °C nor K fits them.
std::string temperature_unit(const Column& col) {
  const std::string& k = col.key;
  const auto ends = [&](std::string_view s) { return k.size() >= s.size() && k.compare(k.size() - s.size(), s.size(), s) == 0; };
  if (ends("_k") || ends("[k]") || ends("(k)") || ends(" k") || contains_any(k, {"kelvin"})) return "K";
  if (ends("_f") || ends("[f]") || ends("(f)") || contains_any(k, {"degf", "°f", "fahrenheit"})) return "°F";
  if (col.q05 >= -60 && col.q95 <= 250) return "°C";
  if (col.q05 >= 200 && col.q95 <= 530) return "K";
  return {};
}

bool has_numbers(const Column& c) { return c.numbers > 0 && !std::isnan(c.median); }

}  // namespace

std::string MapSuggestion::text() const {
  std::string head = "A data map proposed by lptn inspect --suggest-map. Check it, edit what is wrong, and save it\n"
                     "as data.toml beside the CSV files: every lptn command then reads them through it.\n";
  if (!evidence.empty()) head += "\n";
  for (const std::string& e : evidence) head += e + "\n";
  if (!problems.empty()) head += "\nTo look at before use:\n";
  for (const std::string& p : problems) head += "  " + p + "\n";
  if (!head.empty() && head.back() == '\n') head.pop_back();
  return format_data_map(map, head);
}

MapSuggestion suggest_data_map_text(std::string_view text, const std::filesystem::path& first, const SuggestHints& hints) {

  MapSuggestion out;
  DataMap& m = out.map;
  m.file.clear();

  // Comment lines before the header.
  LineSplitter lines(text);
  std::string_view line;
  std::vector<std::string_view> head;  // header first, then rows
  while (lines.next(line)) {
    const std::string_view t = trim(line);
    if (t.empty()) continue;
    if (head.empty()) {
      bool comment = false;
      for (const std::string_view prefix : {"#", "//"}) {
        if (t.substr(0, prefix.size()) == prefix) {
          m.comment = std::string(prefix);
          comment = true;
        }
      }
      if (comment) continue;
    } else if (is_comment(line, m.comment)) {
      continue;
    }
    head.push_back(line);
    if (head.size() > 200) break;
  }
  if (head.size() < 2) throw DataError(first.string() + ": no header and data rows to propose a data map from");
  m.separator = detect_separator(head);
  m.decimal = detect_decimal({head.begin() + 1, head.end()}, m.separator);

  std::vector<Column> cols;
  {
    CellSplitter cells(head.front(), m.separator);
    std::string_view cell;
    while (cells.next(cell)) {
      Column c;
      c.name = hostio::as_utf8(unquoted(cell));
      c.key = lower(c.name);
      cols.push_back(std::move(c));
    }
  }

  // Every row of the first file: the values of the first kSampleRows, each row's cells as text for
  // the time column and a split column.
  LineSplitter rows(text);
  bool header_seen = false;
  std::vector<std::string_view> all_rows;
  while (rows.next(line)) {
    const std::string_view t = trim(line);
    if (t.empty() || is_comment(line, m.comment)) continue;
    if (!header_seen) {
      header_seen = true;
      continue;
    }
    if (internal::count_cells(line, m.separator) != cols.size()) continue;
    all_rows.push_back(line);
  }
  const std::size_t sampled = std::min(all_rows.size(), kSampleRows);
  for (Column& c : cols) c.values.assign(sampled, kNaN);
  std::vector<std::string_view> previous(cols.size());
  for (std::size_t r = 0; r < sampled; ++r) {
    CellSplitter cells(all_rows[r], m.separator);
    std::string_view cell;
    for (std::size_t j = 0; cells.next(cell) && j < cols.size(); ++j) {
      Column& c = cols[j];
      cell = unquoted(cell);
      if (r > 0 && cell != previous[j]) ++c.changes;
      previous[j] = cell;
      if (cell.empty()) continue;
      double v = 0;
      if (internal::parse_number(cell, m.decimal, v) == NumberStatus::ok) {
        c.values[r] = v;
        ++c.numbers;
        continue;
      }
      ++c.texts;
      if (parse_iso8601(cell, v)) ++c.iso;
      if (c.text_counts.size() < 16 || c.text_counts.count(std::string(cell))) ++c.text_counts[std::string(cell)];
    }
  }
  for (Column& c : cols) summarize(c);
  const auto note = [&](std::string s) { out.evidence.push_back(std::move(s)); };
  const auto problem = [&](std::string s) { out.problems.push_back(std::move(s)); };
  // A column without a name, or with the name of one before it, cannot be named in a map (the
  // loader refuses a repeated name): left out of it, and said.
  for (std::size_t j = 0; j < cols.size(); ++j) {
    if (cols[j].name.empty()) {  // a data frame's index, written by pandas' to_csv: read by no one
      cols[j].taken = true;
      if (std::find(m.ignore.begin(), m.ignore.end(), "") == m.ignore.end()) m.ignore.emplace_back();
      note(strf("Column %zu has no name (a data frame's index?): ignored.", j + 1));
    }
    for (std::size_t i = 0; i < j && !cols[j].taken; ++i) {
      if (cols[i].name != cols[j].name) continue;
      cols[j].taken = true;
      problem(strf("columns %zu and %zu are both named '%s': rename one (lptn refuses a repeated name)", i + 1, j + 1,
                   cols[j].name.c_str()));
    }
  }
  note(strf("Read %s: separator '%s', decimal mark '%c'%s; %zu columns, %zu rows (values of the first %zu).",
            first.filename().string().c_str(), m.separator == '\t' ? "\\t" : std::string(1, m.separator).c_str(),
            m.decimal, m.comment.empty() ? "" : strf(", comment lines start with '%s'", m.comment.c_str()).c_str(),
            cols.size(), all_rows.size(), sampled));

  // Time: a date-time column, else a named or strictly increasing numeric one.
  std::optional<std::size_t> time;
  // Not a column left out above (no name, a repeated name): a pandas index 0, 1, 2... increases too.
  for (std::size_t j = 0; j < cols.size() && !time; ++j) {
    if (!cols[j].taken && cols[j].iso > 0 && cols[j].iso * 10 >= (cols[j].iso + cols[j].numbers) * 9) {
      time = j;
      m.time_format = TimeFormat::iso8601;
    }
  }
  const auto increasing = [&](const Column& c) {
    if (c.numbers < sampled * 99 / 100 || c.numbers < 2) return false;
    double last = -std::numeric_limits<double>::infinity();
    for (double v : c.values) {
      if (std::isnan(v)) continue;
      if (v < last) return false;
      last = v;
    }
    return c.max > c.min;
  };
  const auto time_name = [](const std::string& k) {
    return k == "t" || k == "ts" || contains_any(k, {"time", "zeit", "timestamp", "sec", "date", "datum"}) ||
           (k.rfind("t_", 0) == 0 && k.size() <= 4);
  };
  for (std::size_t pass = 0; pass < 2 && !time; ++pass) {
    for (std::size_t j = 0; j < cols.size() && !time; ++j) {
      if (!cols[j].taken && (pass == 1 || time_name(cols[j].key)) && increasing(cols[j])) time = j;
    }
  }
  if (time) {
    Column& c = cols[*time];
    c.taken = true;
    m.time_column = c.name;
    if (m.time_format != TimeFormat::iso8601) {
      std::vector<double> steps;
      for (std::size_t r = 1; r < sampled; ++r)
        if (!std::isnan(c.values[r]) && !std::isnan(c.values[r - 1])) steps.push_back(c.values[r] - c.values[r - 1]);
      const double step = quantile(steps, 0.5);
      const bool ms = contains_any(c.key, {"ms", "milli"}) || c.min > 1e11 || step >= 20;
      m.time_format = ms ? TimeFormat::milliseconds : TimeFormat::seconds;
      note(strf("%s -> time in %s: its values increase, a median step of %s %s.", c.name.c_str(),
                ms ? "milliseconds" : "seconds", internal::num(step).c_str(), ms ? "ms" : "s"));
    } else {
      note(strf("%s -> time: ISO-8601 date-times (%s ...).", c.name.c_str(), c.text_counts.begin()->first.c_str()));
    }
  } else {
    problem("no time column found (a column of increasing numbers, or of date-times): set [time] column and format");
  }

  // Channels by name first, strongest names first; then the rest by their values.
  std::vector<std::optional<Choice>> chosen(kNumChannels);
  const auto take = [&](Channel ch, std::size_t j, std::string unit, std::string why) {
    cols[j].taken = true;
    chosen[index_of(ch)] = Choice{ch, j, std::move(unit), std::move(why)};
  };
  const auto plausible = [&](Channel ch, const Column& c) -> std::optional<std::string> {
    if (!has_numbers(c)) return std::nullopt;
    if (is_temperature_channel(ch)) {
      std::string u = temperature_unit(c);
      if (u.empty()) return std::nullopt;
      return u;
    }
    switch (ch) {
      case Channel::speed_rpm: return std::fabs(c.max) <= 20000 && std::fabs(c.min) <= 20000 ? std::optional<std::string>("rpm") : std::nullopt;
      case Channel::frequency_hz: return std::fabs(c.max) <= 1000 && std::fabs(c.min) <= 1000 ? std::optional<std::string>("Hz") : std::nullopt;
      case Channel::current_a: return c.q05 >= -1 && c.max <= 20000 ? std::optional<std::string>("A") : std::nullopt;
      case Channel::torque_nm: return std::fabs(c.max) <= 1e5 ? std::optional<std::string>("Nm") : std::nullopt;
      case Channel::voltage_v: return c.min >= 0 && c.max <= 20000 ? std::optional<std::string>("V") : std::nullopt;
      case Channel::airflow_m3s: return c.min >= 0 ? std::optional<std::string>("m³/s") : std::nullopt;
      default: return std::nullopt;
    }
  };
  // A column under lptn's own name of a channel or of the time is that one's, or no one's: the map
  // reads it there by default, and a second reader of one column is an error.
  for (Column& c : cols) {
    if (c.name == m.time_column) c.taken = true;
  }
  for (int strength = 3; strength >= 1; --strength) {
    for (Channel ch : kAllChannels) {
      if (chosen[index_of(ch)]) continue;
      for (std::size_t j = 0; j < cols.size(); ++j) {
        if (cols[j].taken || name_score(ch, cols[j].key) != strength) continue;
        // A temperature by name must also read like one (T_ or temp in its name, or its values).
        if (is_temperature_channel(ch) && strength < 3 && !contains_any(cols[j].key, {"temp", "t_", "_t", "°", "deg"}) &&
            temperature_unit(cols[j]).empty())
          continue;
        if (const auto unit = plausible(ch, cols[j])) {
          take(ch, j, *unit, strength == 3 ? "lptn's own name" : strength == 2 ? "its name" : "its name's letter");
          break;
        }
      }
    }
  }

  for (Column& c : cols) {
    if (std::any_of(kAllChannels.begin(), kAllChannels.end(), [&](Channel ch) { return c.name == channel_name(ch); }))
      c.taken = true;
  }

  // Speed and frequency by their ratio: 60/p rpm per Hz, less the slip.
  const auto ratio_of = [&](std::size_t a, std::size_t b) {
    std::vector<double> r;
    const double big = 0.1 * std::max(std::fabs(cols[b].max), std::fabs(cols[b].min));
    for (std::size_t i = 0; i < sampled; ++i) {
      const double x = cols[a].values[i], y = cols[b].values[i];
      if (!std::isnan(x) && !std::isnan(y) && std::fabs(y) > big && big > 0) r.push_back(x / y);
    }
    if (r.size() < 20) return kNaN;
    const double med = quantile(r, 0.5), lo = quantile(r, 0.25), hi = quantile(r, 0.75);
    return med > 0 && (hi - lo) < 0.1 * med ? med : kNaN;
  };
  auto& speed = chosen[index_of(Channel::speed_rpm)];
  auto& freq = chosen[index_of(Channel::frequency_hz)];
  if (!speed || !freq) {
    for (std::size_t a = 0; a < cols.size() && !(speed && freq); ++a) {
      for (std::size_t b = 0; b < cols.size() && !(speed && freq); ++b) {
        if (a == b || !has_numbers(cols[a]) || !has_numbers(cols[b])) continue;
        if ((speed && speed->column != a) || (freq && freq->column != b)) continue;
        if ((!speed && cols[a].taken) || (!freq && cols[b].taken)) continue;
        const double r = ratio_of(a, b);
        if (!(r >= 5 && r <= 65)) continue;
        const int p = hints.pole_pairs > 0 ? hints.pole_pairs : static_cast<int>(std::lround(60.0 / r));
        if (p < 1 || std::fabs(r * p / 60.0 - 1.0) > 0.15) continue;
        const std::string why = strf("its values: %.1f rpm per Hz against the other (%d pole pairs)", r, p);
        if (!speed) take(Channel::speed_rpm, a, "rpm", why);
        if (!freq) take(Channel::frequency_hz, b, "Hz", why);
      }
    }
  }
  if (speed && freq) {
    const double r = ratio_of(speed->column, freq->column);
    if (r > 0 && r < 4) {
      speed->unit = "rad/s";  // 2*pi/p rad/s per Hz: the speed column is angular
      speed->why += strf("; %.2f per Hz against %s: rad/s", r, cols[freq->column].name.c_str());
    }
  }

  // The rest by their values, each only where one column alone fits: a guess between two columns
  // is left to the user, named. Slowness: the 90th percentile of a column's change over 60 s
  // against its spread (temperatures and a blower's airflow well below 0.7, currents near 1).
  // Every row's time in seconds (NaN where none): the sampled rows' for slowness, all for pauses.
  std::vector<double> row_t(all_rows.size(), kNaN);
  if (time) {
    for (std::size_t r = 0; r < all_rows.size(); ++r) {
      CellSplitter cells(all_rows[r], m.separator);
      std::string_view cell;
      for (std::size_t j = 0; cells.next(cell) && j <= *time; ++j) {
        if (j != *time) continue;
        cell = unquoted(cell);
        double t = 0;
        if (m.time_format == TimeFormat::iso8601) {
          if (parse_iso8601(cell, t)) row_t[r] = t;
        } else if (internal::parse_number(cell, m.decimal, t) == NumberStatus::ok) {
          row_t[r] = m.time_format == TimeFormat::milliseconds ? t / 1000.0 : t;
        }
      }
    }
  }
  const auto slowness = [&](const Column& c) {
    std::vector<std::pair<double, double>> pts;
    for (std::size_t r = 0; r < sampled; ++r)
      if (!std::isnan(c.values[r]) && !std::isnan(row_t[r])) pts.emplace_back(row_t[r], c.values[r]);
    std::vector<double> d;
    std::size_t k = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      while (k < pts.size() && pts[k].first < pts[i].first + 60) ++k;
      if (k == pts.size()) break;
      d.push_back(std::fabs(pts[k].second - pts[i].second));
    }
    const double spread = c.q95 - c.q05;
    return d.size() < 10 || !(spread > 0) ? kNaN : quantile(d, 0.9) / spread;
  };
  std::vector<double> slow(cols.size(), kNaN);
  for (std::size_t j = 0; j < cols.size(); ++j)
    if (!cols[j].taken && has_numbers(cols[j])) slow[j] = slowness(cols[j]);
  const auto free_columns = [&](auto&& fits) {
    std::vector<std::size_t> out_cols;
    for (std::size_t j = 0; j < cols.size(); ++j)
      if (!cols[j].taken && has_numbers(cols[j]) && fits(cols[j], slow[j])) out_cols.push_back(j);
    return out_cols;
  };
  const auto names_of = [&](const std::vector<std::size_t>& js) {
    std::string list;
    for (std::size_t j : js) list += (list.empty() ? "" : ", ") + cols[j].name;
    return list;
  };
  const auto one_of = [&](Channel ch, const std::vector<std::size_t>& candidates, const std::string& unit,
                          const std::string& why) {
    if (chosen[index_of(ch)] || candidates.empty()) return;
    if (candidates.size() == 1) {
      take(ch, candidates.front(), unit, why);
    } else {
      problem(strf("%s: its values cannot tell which of %s it is; name one under [columns]",
                   std::string(channel_name(ch)).c_str(), names_of(candidates).c_str()));
    }
  };
  // Torque: the only channel of both signs once speed is known (a motor brakes).
  one_of(Channel::torque_nm,
         free_columns([](const Column& c, double) { return c.negative_share > 0.03 && c.q05 < -0.05 * c.max; }), "Nm",
         "its values (both signs: driving and braking)");
  // Stator and rotor: slow, in a temperature's range, warmer than anything else slow.
  {
    std::vector<std::size_t> temps = free_columns([&](const Column& c, double sl) {
      return !temperature_unit(c).empty() && sl < 0.7 && c.q95 > c.q05;
    });
    const auto celsius = [&](std::size_t j) {
      const auto u = find_unit(Channel::stator_winding_c, temperature_unit(cols[j]));
      return cols[j].median * u->scale + u->offset;
    };
    std::sort(temps.begin(), temps.end(), [&](std::size_t x, std::size_t y) { return celsius(x) < celsius(y); });
    const auto by_value = [&](Channel ch, std::size_t j) {
      take(ch, j, temperature_unit(cols[j]),
           strf("its values (%s..%s, slow: a temperature)", internal::num(cols[j].q05).c_str(),
                internal::num(cols[j].q95).c_str()));
    };
    // The motor's two sensors read warmer than 30 degC most of the time; the air and the airflow do not.
    std::vector<std::size_t> warm;
    for (std::size_t j : temps)
      if (celsius(j) > 30) warm.push_back(j);
    const bool stator_free = !chosen[index_of(Channel::stator_winding_c)], rotor_free = !chosen[index_of(Channel::rotor_c)];
    const std::size_t wanted = static_cast<std::size_t>(stator_free) + static_cast<std::size_t>(rotor_free);
    if (wanted > 0 && warm.size() == wanted) {
      if (stator_free) by_value(Channel::stator_winding_c, warm.back());
      if (rotor_free) by_value(Channel::rotor_c, warm.front());
      if (stator_free && rotor_free)
        problem(strf("%s and %s are told apart by their medians alone (the stator winding taken as the warmer): "
                     "check them",
                     cols[warm.back()].name.c_str(), cols[warm.front()].name.c_str()));
    } else if (wanted > 0 && warm.size() > wanted) {
      problem(strf("stator_winding_c, rotor_c: more slow warm columns than sensors (%s); name them under [columns]",
                   names_of(warm).c_str()));
    }
  }
  // The air: slow, between -40 and 45 degC, a small spread.
  one_of(Channel::ambient_c, free_columns([&](const Column& c, double sl) {
           const std::string u = temperature_unit(c);
           if (u.empty() || !(sl < 0.7)) return false;
           const auto conv = find_unit(Channel::ambient_c, u);
           const double med = c.median * conv->scale + conv->offset;
           return med > -40 && med < 45 && (c.q95 - c.q05) * conv->scale < 25;
         }),
         "", "its values (slow, -40..45 degC, a small spread: the air)");
  if (auto& amb = chosen[index_of(Channel::ambient_c)]; amb && amb->unit.empty()) amb->unit = temperature_unit(cols[amb->column]);
  // Current and voltage need the nameplate to be told from each other and from the airflow.
  if (hints.rated_current_a > 0)
    one_of(Channel::current_a, free_columns([&](const Column& c, double sl) {
             return c.q05 >= -1 && c.q95 > 0.3 * hints.rated_current_a && c.q95 < 3 * hints.rated_current_a && sl > 0.7;
           }),
           "A", "its values (non-negative, fast, the size of the rated current)");
  if (hints.rated_voltage_v > 0)
    one_of(Channel::voltage_v, free_columns([&](const Column& c, double sl) {
             return c.min >= 0 && c.q95 > 0.5 * hints.rated_voltage_v && c.q95 < 2.5 * hints.rated_voltage_v && sl > 0.7;
           }),
           "V", "its values (the size of the rated voltage)");
  one_of(Channel::airflow_m3s, free_columns([](const Column& c, double sl) { return c.min >= 0 && sl < 0.8; }), "m³/s",
         "its values (non-negative, slow)");

  // Airflow's unit by its size: against the motor's nominal airflow, else by the name, else by magnitude.
  if (auto& air = chosen[index_of(Channel::airflow_m3s)]) {
    const Column& c = cols[air->column];
    const std::string& k = c.key;
    const auto ends = [&](std::string_view e) { return k.size() >= e.size() && k.compare(k.size() - e.size(), e.size(), e) == 0; };
    if (contains_any(k, {"l/s", "liter", "litre"}) || ends("_ls") || ends("lps") || ends("_l_s")) {
      air->unit = "l/s";
    } else if (contains_any(k, {"m3/h", "m³/h", "m3_h"}) || ends("m3h") || ends("cmh")) {
      air->unit = "m³/h";
    } else if (contains_any(k, {"cfm"})) {
      air->unit = "cfm";
    } else if (hints.nominal_airflow_m3s > 0) {
      double best = std::numeric_limits<double>::infinity();
      for (const UnitConversion& u : units_of(Channel::airflow_m3s)) {
        if (u.unit == "m3/s" || u.unit == "L/s" || u.unit == "m3/h" || u.unit == "L/min") continue;
        const double d = std::fabs(std::log(c.median * u.scale / hints.nominal_airflow_m3s));
        if (d < best) {
          best = d;
          air->unit = std::string(u.unit);
        }
      }
      air->why += "; its unit by the motor file's nominal airflow";
    } else if (c.median > 20) {
      air->unit = "l/s";
      problem(strf("the unit of %s (about %s) is a guess, l/s: it may be m³/h; --motor lets the motor's nominal "
                   "airflow decide", c.name.c_str(), internal::num(c.median).c_str()));
    }
  }

  for (Channel ch : kAllChannels) {
    const auto& ch_choice = chosen[index_of(ch)];
    if (!ch_choice) {
      if (channel_info(ch).required)
        problem(strf("no column found for %s (required): add %s = { column = \"...\", unit = \"%.*s\" } under [columns]",
                     std::string(channel_name(ch)).c_str(), std::string(channel_name(ch)).c_str(),
                     static_cast<int>(channel_info(ch).unit.size()), channel_info(ch).unit.data()));
      else
        note(strf("No column found for %s (optional).", std::string(channel_name(ch)).c_str()));
      continue;
    }
    const Column& c = cols[ch_choice->column];
    ColumnSource src;
    src.column = c.name;
    const auto u = find_unit(ch, ch_choice->unit);
    const auto identity = units_of(ch).front();
    if (u && !(u->scale == identity.scale && u->offset == identity.offset)) {
      src.unit = ch_choice->unit;
      src.scale = u->scale;
      src.offset = u->offset;
    }
    if (src.column != channel_name(ch) || !src.unit.empty()) m.columns[index_of(ch)] = src;
    note(strf("%s -> %s%s: by %s.", c.name.c_str(), std::string(channel_name(ch)).c_str(),
              src.unit.empty() ? "" : (" in " + src.unit).c_str(), ch_choice->why.c_str()));
  }

  // Missing-value texts; other text in a number column is named.
  for (const Column& c : cols) {
    if (time && &c == &cols[*time]) continue;
    for (const auto& [t, n] : c.text_counts) {
      if (is_missing_token(t)) {
        if (std::find(m.missing.begin(), m.missing.end(), t) == m.missing.end()) m.missing.push_back(t);
      } else if (c.taken && c.numbers > 0) {
        problem(strf("column %s holds the text '%s' in %zu rows: list it under [csv] missing if it means no value",
                     c.name.c_str(), t.c_str(), n));
      }
    }
  }

  // A trip or drive column splits the file; else long pauses at standstill do.
  for (Column& c : cols) {
    if (c.taken) continue;
    if (contains_any(c.key, {"trip", "fahrt", "drive", "journey", "ride", "mission", "run_id", "tour"}) &&
        c.changes * 100 < sampled + 100) {
      m.split_column = c.name;
      c.taken = true;
      note(strf("%s -> split: the file is cut at every change of its value (%zu changes in the rows read).",
                c.name.c_str(), c.changes));
      break;
    }
  }
  if (time && m.split_column.empty()) {
    const auto& sp = chosen[index_of(Channel::speed_rpm)];
    const double still = sp ? 0.05 * std::max(std::fabs(cols[sp->column].max), std::fabs(cols[sp->column].min)) : 0.0;
    const auto standing = [&](std::size_t r) {
      if (!sp || r >= sampled) return !sp;
      const double v = cols[sp->column].values[r];
      return !std::isnan(v) && std::fabs(v) <= still;
    };
    // A pause at standstill longer than 5 minutes ends a drive; any pause longer than 20 minutes
    // does (a logger that stops with the train may stop before the speed reads zero).
    constexpr double kStandstillPauseS = 300, kPauseS = 1200;
    std::size_t standstill_pauses = 0, long_pauses = 0;
    double prev = kNaN;
    for (std::size_t r = 0; r < all_rows.size(); ++r) {
      const double t = row_t[r];  // the whole file's rows, not only those whose values were read
      if (std::isnan(t)) continue;
      if (!std::isnan(prev)) {
        const double gap = t - prev;
        if (gap > kPauseS) {
          ++long_pauses;
        } else if (gap > kStandstillPauseS && sp && standing(r) && r > 0 && standing(r - 1)) {
          ++standstill_pauses;
        }
      }
      prev = t;
    }
    if (standstill_pauses + long_pauses > 0) {
      m.split_pause_s = standstill_pauses > 0 ? kStandstillPauseS : kPauseS;
      note(strf("Pauses: %zu longer than %.0f s%s in this file; [split] cuts it into %zu drives at pauses longer than "
                "%.0f s.",
                long_pauses, kPauseS,
                standstill_pauses ? strf(", %zu more at standstill", standstill_pauses).c_str() : "",
                standstill_pauses + long_pauses + 1, m.split_pause_s));
    }
  }

  // Every column the map does not read is ignored, but one the map reads by default (lptn's own
  // name of a channel or of the time, which it could not confirm): a map may not ignore what it reads.
  const auto read_by_default = [&](const std::string& name) {
    if (name == m.time_column || name == m.split_column) return true;
    return std::any_of(kAllChannels.begin(), kAllChannels.end(), [&](Channel ch) { return m.source_of(ch) == name; });
  };
  for (const Column& c : cols) {
    if (!c.taken && !read_by_default(c.name) &&
        std::find(m.ignore.begin(), m.ignore.end(), c.name) == m.ignore.end())
      m.ignore.push_back(c.name);
  }
  if (!m.ignore.empty()) {
    std::string list;
    for (const std::string& n : m.ignore) list += (list.empty() ? "" : ", ") + n;
    note("Not read (ignore): " + list + ".");
  }

  return out;
}

MapSuggestion suggest_data_map(const std::vector<std::filesystem::path>& paths, const SuggestHints& hints) {
  const std::vector<std::filesystem::path> files = cycle_files(paths);
  if (files.empty()) throw DataError("no CSV file to propose a data map for");
  // The first line that is neither blank nor a comment, without a byte-order mark.
  const auto header_of = [](std::istream& in, const std::string& comment) {
    std::string l;
    while (std::getline(in, l)) {
      if (!l.empty() && l.back() == '\r') l.pop_back();
      if (l.substr(0, 3) == "\xEF\xBB\xBF") l.erase(0, 3);
      if (trim(l).empty() || is_comment(l, comment)) continue;
      return l;
    }
    return std::string();
  };
  const std::filesystem::path& first = files.front();
  std::ifstream in(first, std::ios::binary);
  if (!in) throw DataError(first.string() + ": cannot open for reading");
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  MapSuggestion out = suggest_data_map_text(text, first, hints);
  // Every file should have the first's header.
  std::istringstream first_text(text);
  const std::string header = header_of(first_text, out.map.comment);
  for (std::size_t f = 1; f < files.size(); ++f) {
    std::ifstream other(files[f], std::ios::binary);
    if (header_of(other, out.map.comment) != header)
      out.problems.push_back(files[f].string() + ": its header differs from " + first.filename().string() +
                             "'s; one map reads both only if their columns are the same");
  }
  return out;
}

}  // namespace lptn::data
