// JSON files lptn writes and reads back (calibration.json, fleet.json, a diagnosis): parsed with
// the line a syntax error stands on, and read field by field with the field's path in every
// complaint, so that a bad file is one line naming file, line or field, and why.
#pragma once

#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "hostio/bad_input.hpp"

namespace lptn::hostio {

// A bad JSON file; one line: "FILE: line N: reason" or "FILE: field 'a.b[3].c': reason".
class JsonFileError : public BadInput {
 public:
  using BadInput::BadInput;
};

// The document in `text`; throws JsonFileError "SHOWN: line N: reason" (the reason without
// nlohmann's exception prefix).
nlohmann::json parse_json_text(const std::string& text, const std::string& shown);
// The file's text; throws JsonFileError "FILE: cannot read (missing or not readable)".
std::string read_text_file(const std::filesystem::path& path);

// A JSON value and its path from the document's root ("data.files[2].sha256"). Every accessor
// checks the type and throws JsonFileError "FILE: field 'PATH': expected a number" (or missing...).
class JsonField {
 public:
  JsonField(const nlohmann::json& value, std::string path, const std::string& file)
      : value_(&value), path_(std::move(path)), file_(&file) {}

  const nlohmann::json& json() const { return *value_; }
  const std::string& path() const { return path_; }
  const std::string& file() const { return *file_; }

  [[noreturn]] void fail(const std::string& why) const;

  bool has(const char* key) const { return value_->is_object() && value_->contains(key); }
  // A member of an object; fails if this is not an object or the member is absent.
  JsonField operator[](const char* key) const;
  // An element of an array (index checked by the caller through size()).
  JsonField at(std::size_t i) const { return JsonField((*value_)[i], path_ + "[" + std::to_string(i) + "]", *file_); }
  std::size_t size() const;  // of an array
  void expect_object() const;

  double number() const;
  double number_or_null() const;  // null stands for "unknown" (NaN) where a field allows it
  long long integer() const;
  std::size_t count() const;  // a whole number, not negative
  bool boolean() const;
  std::string string() const;

 private:
  const nlohmann::json* value_;
  std::string path_;
  const std::string* file_;
};

}  // namespace lptn::hostio
