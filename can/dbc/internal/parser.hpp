// The DBC grammar: tokens and statements, what check.cpp checks and resolves. Internal to can/dbc.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "can/dbc/dbc.hpp"

namespace lptn::dbc::internal {

struct Token {
  enum class Kind { ident, number, string, punct, eof };
  Kind kind;
  std::string text;
  int line;
};

// Throws ParseError(line, reason); dbc.cpp adds the file.
struct ParseError {
  int line;
  std::string reason;
};

std::vector<Token> tokenize(std::string_view text);

// A DBC number: its text and value (whole numbers exactly, up to 2^63).
struct Number {
  std::string text;
  double value = 0;
  bool whole = false;  // no '.', no fraction: 12, 1e+09
  long long integer = 0;
};

using Value = std::variant<Number, std::string>;

struct RawSignal {
  Signal signal;  // its receivers, texts and layout; check.cpp fills in the rest
  Number factor, offset, minimum, maximum;
};

struct RawMessage {
  std::uint64_t dbc_id;  // as written, with the extended flag
  std::string name, sender;
  int line;
  long long dlc;
  std::vector<RawSignal> signals;
};

struct AttributeDef {
  int line;
  std::string object_kind, type;
  Number minimum, maximum;
  std::vector<std::string> choices;
};

// Statements naming other objects, resolved in file order once the file is read.
struct Statement {
  enum class Kind { comment, attr_default, attr_value, values, value_type, transmitters, mux_values };
  Kind kind;
  int line;
  std::string name;        // attribute name, or the signal's
  std::string object_kind;  // CM_, BA_: BU_, BO_, SG_, EV_ or "" (the network)
  std::uint64_t message_id = 0;  // an integer as written: negative ids wrap (and name no message)
  std::string signal;      // CM_/BA_ SG_, VAL_, SIG_VALTYPE_, SG_MUL_VAL_; CM_/BA_ BU_ and EV_: the name
  std::string text;        // CM_
  std::vector<std::pair<long long, std::string>> pairs;  // VAL_
  std::vector<std::string> nodes;  // BO_TX_BU_
  Value value;
  long long value_type = 0;
  std::string multiplexor;
  std::vector<std::pair<long long, long long>> ranges;
};

struct Document {
  std::vector<std::pair<std::string, int>> nodes;
  std::optional<int> nodes_line;
  std::vector<RawMessage> messages;
  std::map<std::string, AttributeDef> attribute_defs;
  std::vector<Statement> statements;
  std::vector<std::pair<int, std::string>> warnings;
};

Document parse_document(const std::vector<Token>& tokens);

}  // namespace lptn::dbc::internal
