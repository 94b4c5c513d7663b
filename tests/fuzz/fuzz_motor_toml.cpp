// Fuzz target: the motor file reader (trainer/model/motor_file.hpp, parse_motor_file), toml++
// underneath. Input: the file's text.
//
// Bad input must come out as MotorFileError, toml++'s own parse errors included (motor_file.cpp
// converts them), as the one line "FILE:LINE: key 'KEY': reason" the command line prints;
// anything else escaping is a finding. What parses must hold what the reader promises to check.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_check.hpp"
#include "motor_invariants.hpp"
#include "trainer/model/motor_file.hpp"

using lptn::model::check_motor;
using lptn::model::MotorFileError;
using lptn::model::parse_motor_file;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    check_motor(parse_motor_file(text, "fuzz.toml"));
  } catch (const MotorFileError& e) {
    LPTN_FUZZ_CHECK(std::string_view(e.what()).find_first_of("\r\n") == std::string_view::npos,
                    "an error message of more than one line");
  }
  return 0;
}
