// Bad input is one line, whatever the input it quotes holds.
#include <gtest/gtest.h>

#include <string>

#include "hostio/bad_input.hpp"

namespace lptn::hostio {
namespace {

TEST(BadInput, ControlCharactersOfTheInputAreWrittenAsEscapes) {
  const hostio::BadInput e(std::string("fuzz.json: field 'motor.parameters.&\n \nda_12s': unknown parameter; tab\there, cr\r, nul ") +
                   std::string(1, '\0') + ", del \x7f, \xc3\xa9 stays");
  const std::string what = e.what();
  EXPECT_EQ(what.find_first_of(std::string("\r\n\t\0\x7f", 5)), std::string::npos) << what;
  EXPECT_EQ(what, "fuzz.json: field 'motor.parameters.&\\n \\nda_12s': unknown parameter; tab\\there, cr\\r, nul \\x00, "
                  "del \\x7f, \xc3\xa9 stays");
}

// Every module's own kind inherits it.
struct OwnError : hostio::BadInput {
  using BadInput::BadInput;
};

TEST(BadInput, DerivedErrorsAreOneLineToo) {
  EXPECT_STREQ(OwnError("a\nb").what(), "a\\nb");
}

}  // namespace
}  // namespace lptn::hostio
