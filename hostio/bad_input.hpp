// Input a user gave that lptn cannot use: a file, one of its lines or fields, a setting. Every
// module's own error of that kind derives from this one type (DataError, MotorFileError,
// JsonFileError, the CAN readers', the exporter's...), so that a program reports all of it in one
// place, as one line and exit code 2, and whatever else escapes is lptn's own failure (exit 1). The
// message is the line the user reads: it names the file, the line or field, and why.
#pragma once

#include <cstdio>
#include <stdexcept>
#include <string>

namespace lptn::hostio {

class BadInput : public std::runtime_error {
 public:
  explicit BadInput(const std::string& message) : std::runtime_error(one_line(message)) {}
  explicit BadInput(const char* message) : BadInput(std::string(message)) {}

  // `text` with its control characters written as escapes (\n, \r, \t, \xNN): a message quotes
  // what the input holds (a JSON key, a CSV field, a TOML string), and a newline there would break
  // the one line a program prints into several (fuzz_motor_json found a key "&\n \nda_12s").
  static std::string one_line(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
      const auto byte = static_cast<unsigned char>(c);
      if (byte >= 0x20 && byte != 0x7f) {
        out += c;
      } else if (c == '\n') {
        out += "\\n";
      } else if (c == '\r') {
        out += "\\r";
      } else if (c == '\t') {
        out += "\\t";
      } else {
        char escaped[8];
        std::snprintf(escaped, sizeof escaped, "\\x%02x", static_cast<unsigned>(byte));
        out += escaped;
      }
    }
    return out;
  }
};

}  // namespace lptn::hostio
