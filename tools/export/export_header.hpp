// lptn export: a calibration as a C++ header for the firmware (constants only, no code of its own
// beyond motor_constants(); it compiles against common/ alone, without exceptions or RTTI).
#pragma once

#include <stdexcept>
#include <string>

#include "hostio/bad_input.hpp"
#include "trainer/calibrate/calibration_file.hpp"

namespace lptn::exporter {

// A calibration that cannot become a header (no actor where one was asked for, a value with no
// literal, an actor shape the firmware's forward pass does not take). One line, naming the file.
class ExportError : public hostio::BadInput {
 public:
  using BadInput::BadInput;
};

struct ExportOptions {
  std::string source_name = "calibration.json";  // shown in the header and as kSourceFile
  bool actor = false;                            // also the TD3 actor's weights (needs lptn/actor.hpp)
};

// The header's full text. Throws ExportError, or MotorFileError if the embedded motor text does not
// parse (named "SOURCE: motor.text:LINE").
std::string export_header(const calibrate::CalibrationResult& calibration, const ExportOptions& options);

}  // namespace lptn::exporter
