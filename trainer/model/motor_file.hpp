// The motor file: what the user knows of the motor (TOML, see docs/model.md "The motor file" and
// ../shared/contracts/motor.example.toml) and which parameters calibration may move.
#pragma once

#include <array>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

#include "hostio/bad_input.hpp"
#include "lptn/model.hpp"

namespace lptn::model {

// A bad motor file; the message is one line: "FILE:LINE: key 'KEY': reason".
class MotorFileError : public hostio::BadInput {
 public:
  using BadInput::BadInput;
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

// What a file holds, told from its content (not its name), so that a file given in the wrong place
// is named for what it is instead of failing in a parser: JSON whose first non-blank character is
// '{' and whose top-level keys are a fleet calibration's (pooled, motors) or a calibration's
// (parameters with motor, metrics or created_utc); a CSV whose first line names time_s; else TOML.
enum class InputKind { motor_toml, calibration_json, fleet_calibration_json, other_json, cycle_csv };
InputKind input_kind(std::string_view text);
// "a calibration file (JSON)", "a fleet calibration (JSON)", "a fleet-dump cycle (CSV)"...
std::string_view input_kind_words(InputKind kind);

// Throws MotorFileError: one line naming the file and what is wrong; a file of another kind (a
// calibration, a fleet calibration, a cycle CSV) is named as such ("cal.json is a calibration file
// (JSON), not a motor file (TOML): give it as --calibration"); a misspelt key gets "did you mean".
MotorFile load_motor_file(const std::filesystem::path& path);
MotorFile parse_motor_file(const std::string& text, const std::filesystem::path& shown_as);

// The file's text for a motor (round-trips through parse_motor_file). Parameters in `values`
// replace the initial values where given (NaN = keep).
std::string format_motor_file(const MotorFile& motor);

}  // namespace lptn::model
