// The motor file: what the user knows of the motor (TOML, see README.md "The motor file" and
// ../shared/contracts/motor.example.toml) and which parameters calibration may move.
#pragma once

#include <array>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "lptn/model.hpp"

namespace lptn {

// A bad motor file; the message is one line: "FILE:LINE: key 'KEY': reason".
class MotorFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ParameterSetting {
  double initial = 0;
  double min = 0;
  double max = 0;
  bool calibrate = true;
  bool in_file = false;  // given in [parameters.NAME], not a library default
};

struct MotorFile {
  std::string name;
  std::filesystem::path path;
  std::string text;  // the file as read (a calibration keeps it, to rebuild the model from the result alone)
  MotorConstants<double> constants;
  EffectSet effects = 0;
  std::array<ParameterSetting, kNumParams> parameters{};

  ParamVector<double> initial_values() const;
  Model<double> model() const { return Model<double>(constants, effects); }
};

// Every parameter with its library defaults, before any file is read.
std::array<ParameterSetting, kNumParams> default_parameter_settings();

MotorFile load_motor_file(const std::filesystem::path& path);
MotorFile parse_motor_file(const std::string& text, const std::filesystem::path& shown_as);

// The file's text for a motor (round-trips through parse_motor_file). Parameters in `values`
// replace the initial values where given (NaN = keep).
std::string format_motor_file(const MotorFile& motor);

}  // namespace lptn
