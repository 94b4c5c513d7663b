// Input a user gave that lptn cannot use: a file, one of its lines or fields, a setting. Every
// module's own error of that kind derives from this one type (DataError, MotorFileError,
// JsonFileError, the CAN readers', the exporter's...), so that a program reports all of it in one
// place, as one line and exit code 2, and whatever else escapes is lptn's own failure (exit 1). The
// message is the line the user reads: it names the file, the line or field, and why.
#pragma once

#include <stdexcept>

namespace lptn {

class BadInput : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace lptn
