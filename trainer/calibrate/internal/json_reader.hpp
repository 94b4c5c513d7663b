// Typed access to a parsed JSON document that names the offending field on any mismatch:
// "FILE: field 'metrics.test.rmse_stator_k': expected a number". Used by the calibration-file reader.
#pragma once

#include <cmath>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "trainer/calibrate/calibration_file.hpp"

namespace lptn::internal {

// A JSON value and its path from the document's root ("data.files[2].sha256").
class JsonField {
 public:
  JsonField(const nlohmann::json& value, std::string path, const std::string& file)
      : value_(&value), path_(std::move(path)), file_(&file) {}

  const nlohmann::json& json() const { return *value_; }
  const std::string& path() const { return path_; }

  [[noreturn]] void fail(const std::string& why) const {
    throw CalibrationFileError(*file_ + ": field '" + path_ + "': " + why);
  }

  bool has(const char* key) const { return value_->is_object() && value_->contains(key); }

  // A member of an object; fails if this is not an object or the member is absent.
  JsonField operator[](const char* key) const {
    expect_object();
    const auto it = value_->find(key);
    const std::string sub = path_.empty() ? std::string(key) : path_ + "." + key;
    if (it == value_->end()) throw CalibrationFileError(*file_ + ": field '" + sub + "': missing");
    return JsonField(*it, sub, *file_);
  }

  // An element of an array (index checked by the caller through size()).
  JsonField at(std::size_t i) const { return JsonField((*value_)[i], path_ + "[" + std::to_string(i) + "]", *file_); }

  std::size_t size() const {
    if (!value_->is_array()) fail("expected an array");
    return value_->size();
  }

  void expect_object() const {
    if (!value_->is_object()) fail("expected an object");
  }

  double number() const {
    if (!value_->is_number()) fail("expected a number");
    return value_->get<double>();
  }
  // null stands for "unknown" (NaN) where a field allows it.
  double number_or_null() const { return value_->is_null() ? std::nan("") : number(); }

  long long integer() const {
    if (!value_->is_number_integer()) fail("expected a whole number");
    return value_->get<long long>();
  }

  std::size_t count() const {
    const long long n = integer();
    if (n < 0) fail("expected a count (not negative)");
    return static_cast<std::size_t>(n);
  }

  bool boolean() const {
    if (!value_->is_boolean()) fail("expected true or false");
    return value_->get<bool>();
  }

  std::string string() const {
    if (!value_->is_string()) fail("expected a string");
    return value_->get<std::string>();
  }

 private:
  const nlohmann::json* value_;
  std::string path_;
  const std::string* file_;
};

}  // namespace lptn::internal
