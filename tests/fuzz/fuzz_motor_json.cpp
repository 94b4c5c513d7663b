// Fuzz target: the motor as calibration.json carries it (trainer/model/motor_json.hpp,
// motor_from_json), nlohmann's parser underneath. Input: the JSON text of the "motor" object.
//
// Bad input must come out as JsonFileError, as the one line "FILE: field 'motor.…': reason" (or
// "FILE: line N: reason") the command line prints; anything else escaping is a finding. What is
// accepted must hold what the motor file's reader promises (the two read by the same rules), write
// back to the same motor, and be a motor the motor file's reader accepts once written as one.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_check.hpp"
#include "hostio/json_file.hpp"
#include "motor_invariants.hpp"
#include "trainer/model/motor_file.hpp"
#include "trainer/model/motor_json.hpp"

using namespace lptn;

namespace {

void check_one_line(const std::exception& e) {
  LPTN_FUZZ_CHECK(std::string_view(e.what()).find_first_of("\r\n") == std::string_view::npos,
                  "an error message of more than one line");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string file = "fuzz.json";
  model::MotorFile motor;
  try {
    const nlohmann::json j = hostio::parse_json_text(text, file);
    motor = model::motor_from_json(hostio::JsonField(j, "motor", file));
  } catch (const hostio::JsonFileError& e) {
    check_one_line(e);
    return 0;
  }
  model::check_motor(motor);
  // Written and read again: the same motor (format_motor_file writes every value it holds).
  const nlohmann::json again = model::motor_json(motor);
  const model::MotorFile back = model::motor_from_json(hostio::JsonField(again, "motor", file));
  LPTN_FUZZ_CHECK(model::format_motor_file(back) == model::format_motor_file(motor) && back.effects == motor.effects,
                  "the motor's JSON does not read back as the same motor");
  // The same rules as the motor file's: what one reader takes, the other takes.
  try {
    model::check_motor(model::parse_motor_file(model::format_motor_file(motor), "written.toml"));
  } catch (const model::MotorFileError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    LPTN_FUZZ_CHECK(false, "a motor the JSON reader took that the motor file's reader refuses");
  }
  return 0;
}
