#include "hostio/json_file.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>

namespace lptn::hostio {
namespace {

std::size_t line_at(const std::string& text, std::size_t offset) {
  const std::size_t end = std::min(offset, text.size());
  return 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(end), '\n'));
}

}  // namespace

nlohmann::json parse_json_text(const std::string& text, const std::string& shown) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    // e.byte is the 1-based position of the character that failed; the line is what a user needs.
    const std::size_t line = line_at(text, e.byte == 0 ? 0 : e.byte - 1);
    // nlohmann's message starts "[json.exception.parse_error.101] parse error at line 3, column 5: ";
    // keep only the reason after it.
    std::string why = e.what();
    const auto column = why.find(", column ");
    const auto colon = column == std::string::npos ? std::string::npos : why.find(": ", column);
    if (colon != std::string::npos) why = why.substr(colon + 2);
    throw JsonFileError(shown + ": line " + std::to_string(line) + ": " + why);
  } catch (const nlohmann::json::exception& e) {
    // A number beyond a double ("[json.exception.out_of_range.406] number overflow parsing '1e400'"):
    // no position comes with it, so the line is where its text first stands.
    std::string why = e.what();
    if (const auto bracket = why.find("] "); why.rfind("[json.exception.", 0) == 0 && bracket != std::string::npos)
      why = why.substr(bracket + 2);
    const auto open = why.find('\''), close = why.rfind('\'');
    const std::size_t at = open < close ? text.find(why.substr(open + 1, close - open - 1)) : std::string::npos;
    throw JsonFileError(shown + (at == std::string::npos ? "" : ": line " + std::to_string(line_at(text, at))) + ": " + why);
  }
}

std::string read_text_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw JsonFileError(path.string() + ": cannot read (missing or not readable)");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void JsonField::fail(const std::string& why) const { throw JsonFileError(*file_ + ": field '" + path_ + "': " + why); }

JsonField JsonField::operator[](const char* key) const {
  expect_object();
  const auto it = value_->find(key);
  const std::string sub = path_.empty() ? std::string(key) : path_ + "." + key;
  if (it == value_->end()) throw JsonFileError(*file_ + ": field '" + sub + "': missing");
  return JsonField(*it, sub, *file_);
}

std::size_t JsonField::size() const {
  if (!value_->is_array()) fail("expected an array");
  return value_->size();
}

void JsonField::expect_object() const {
  if (!value_->is_object()) fail("expected an object");
}

double JsonField::number() const {
  if (!value_->is_number()) fail("expected a number");
  return value_->get<double>();
}

double JsonField::number_or_null() const { return value_->is_null() ? std::nan("") : number(); }

long long JsonField::integer() const {
  if (!value_->is_number_integer()) fail("expected a whole number");
  return value_->get<long long>();
}

std::size_t JsonField::count() const {
  const long long n = integer();
  if (n < 0) fail("expected a count (not negative)");
  return static_cast<std::size_t>(n);
}

bool JsonField::boolean() const {
  if (!value_->is_boolean()) fail("expected true or false");
  return value_->get<bool>();
}

std::string JsonField::string() const {
  if (!value_->is_string()) fail("expected a string");
  return value_->get<std::string>();
}

}  // namespace lptn::hostio
