// "did you mean ...?" for a misspelt name: the known name nearest by edit distance, if near enough
// to be a typo rather than another word (the loader's columns, the motor file's keys).
#pragma once

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace lptn::data {

// Levenshtein distance, letters compared without case (a column "Rotor_C" is a typo too).
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  const auto same = [](char x, char y) {
    return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
  };
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same(a[i - 1], b[j - 1]) ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// The known name nearest to `word`, or "" when none is within a third of the word's length (at
// least 2 edits): "stator_resistence_20c_ohm" finds "stator_resistance_20c_ohm", "colour" nothing.
// Ties go to the first in `known`.
template <class Names>
std::string closest_name(std::string_view word, const Names& known) {
  const std::size_t limit = std::max<std::size_t>(2, word.size() / 3);
  std::string best;
  std::size_t best_distance = limit + 1;
  for (const auto& name : known) {
    const std::string_view n(name);
    if (n == word) continue;
    const std::size_t d = edit_distance(word, n);
    if (d < best_distance) {
      best_distance = d;
      best = std::string(n);
    }
  }
  return best;
}

// " (did you mean 'NAME'?)", or "" when no known name is near.
template <class Names>
std::string did_you_mean(std::string_view word, const Names& known) {
  const std::string best = closest_name(word, known);
  return best.empty() ? std::string() : " (did you mean '" + best + "'?)";
}

}  // namespace lptn::data
