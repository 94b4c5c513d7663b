#pragma once
// Allocation-free CSV tokenizing and number parsing for fleet dumps. No quoting: the dumps are
// numbers and plain column names, and supporting quoted commas would cost every cell a check.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <string_view>
#include <system_error>

namespace lptn::data::internal {

inline std::string_view trim(std::string_view s) {
  const auto blank = [](char c) { return c == ' ' || c == '\t'; };
  std::size_t b = 0, e = s.size();
  while (b < e && blank(s[b])) ++b;
  while (e > b && blank(s[e - 1])) --e;
  return s.substr(b, e - b);
}

// A cell without blanks and the double quotes some exports put around every cell (a header name
// always, a data cell where a data map reads the file).
inline std::string_view unquoted(std::string_view cell) {
  cell = trim(cell);
  if (cell.size() >= 2 && cell.front() == '"' && cell.back() == '"') cell = trim(cell.substr(1, cell.size() - 2));
  return cell;
}

// A line a data map's [csv] comment prefix marks as a comment (none when the prefix is empty).
inline bool is_comment(std::string_view line, std::string_view prefix) {
  return !prefix.empty() && trim(line).substr(0, prefix.size()) == prefix;
}

// Walks a buffer line by line; accepts LF and CRLF (one trailing '\r' is dropped).
class LineSplitter {
 public:
  explicit LineSplitter(std::string_view text) : text_(text) {
    // A UTF-8 byte order mark from spreadsheet exports would otherwise glue onto the first name.
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") pos_ = 3;
  }

  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const char* begin = text_.data() + pos_;
    const std::size_t left = text_.size() - pos_;
    const void* nl = std::memchr(begin, '\n', left);
    const std::size_t len = nl ? static_cast<std::size_t>(static_cast<const char*>(nl) - begin) : left;
    line = std::string_view(begin, len);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ += len + 1;
    ++number_;
    return true;
  }

  // 1-based number of the line last returned by next().
  std::size_t line_number() const { return number_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t number_ = 0;
};

inline std::size_t count_cells(std::string_view line, char separator = ',') {
  return 1 + static_cast<std::size_t>(std::count(line.begin(), line.end(), separator));
}

// Yields the cells of one line (comma-separated, or as a data map says), untrimmed.
class CellSplitter {
 public:
  explicit CellSplitter(std::string_view line, char separator = ',') : line_(line), separator_(separator) {}

  bool next(std::string_view& cell) {
    if (done_) return false;
    const std::size_t comma = line_.find(separator_, pos_);
    if (comma == std::string_view::npos) {
      cell = line_.substr(pos_);
      done_ = true;
    } else {
      cell = line_.substr(pos_, comma - pos_);
      pos_ = comma + 1;
    }
    return true;
  }

 private:
  std::string_view line_;
  char separator_;
  std::size_t pos_ = 0;
  bool done_ = false;
};

enum class NumberStatus { ok, empty, not_a_number, non_finite, out_of_range };

// `cell` untrimmed. Only a whole-cell decimal or scientific number is ok; "nan"/"inf" text is
// reported separately because from_chars would happily accept it.
inline NumberStatus parse_number(std::string_view cell, double& out) {
  cell = trim(cell);
  if (cell.empty()) return NumberStatus::empty;
  const char* first = cell.data();
  const char* last = cell.data() + cell.size();
  // from_chars rejects a leading '+', which some loggers write; a sign after it stays an error.
  if (*first == '+' && cell.size() > 1 && first[1] != '-' && first[1] != '+') ++first;
  double value = 0;
  const auto [ptr, ec] = std::from_chars(first, last, value, std::chars_format::general);
  if (ec == std::errc::result_out_of_range) return NumberStatus::out_of_range;
  if (ec != std::errc() || ptr != last) return NumberStatus::not_a_number;
  if (!std::isfinite(value)) return NumberStatus::non_finite;
  out = value;
  return NumberStatus::ok;
}

// The same with a decimal comma (a data map's decimal = ","): the cell is read with '.' for ','.
inline NumberStatus parse_number(std::string_view cell, char decimal, double& out) {
  if (decimal == '.') return parse_number(cell, out);
  cell = trim(cell);
  char buf[96];
  if (cell.size() > sizeof buf) return NumberStatus::not_a_number;
  for (std::size_t i = 0; i < cell.size(); ++i) {
    if (cell[i] == '.') return NumberStatus::not_a_number;  // a point is no decimal mark here
    buf[i] = cell[i] == decimal ? '.' : cell[i];
  }
  return parse_number(std::string_view(buf, cell.size()), out);
}

}  // namespace lptn::data::internal
