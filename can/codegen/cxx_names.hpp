// The names the codecs give a DBC's messages, signals and values in C++. Different DBC names can meet
// in C++ (TC_Speed and TcSpeed, Speed and speed_decode, a signal GEAR with values in a message GEAR):
// the later one is renamed, with a warning; a name C++ cannot have stops the generation.
#pragma once

#include <string>
#include <vector>

#include "can/dbc/dbc.hpp"

namespace lptn::codegen {

struct SignalNames {
  std::string base;    // snake case: NAME_decode() etc.
  std::string member;  // the struct member: base, with '_' where it is a keyword or pack()'s local
  std::string enum_name;  // of its VAL_, if it has values
  std::vector<std::string> enumerators;
};
struct MessageNames {
  std::string type;  // the struct
  std::vector<SignalNames> signals;
};

// Throws dbc::Error ("FILE:LINE: reason"); renames go to `warnings`.
std::vector<MessageNames> cxx_names(const dbc::Database& db, std::vector<dbc::Warning>& warnings);

// TC_Electrical -> TcElectrical; a leading digit gets an N (2017_5 -> N20175).
std::string camel_case(const std::string& name);
// MotorSpeed -> motor_speed, ABSActive -> abs_active; 0_COUNTER -> n_0_counter.
std::string snake_case(const std::string& name);
// Descriptions as enumerators; repeated ones ("reserved") get their value appended.
std::vector<std::string> enumerator_names(const std::vector<std::pair<std::int64_t, std::string>>& values);

}  // namespace lptn::codegen
