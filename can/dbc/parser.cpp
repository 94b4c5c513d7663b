// Tokens and statements of a DBC file: the one grammar the build (lptn-can-codegen) and the run-time
// readers read it by. Messages are word for word those of the Python generator this replaced, so
// that the refusals the tests expect stay.
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <set>

#include "can/dbc/internal/parser.hpp"

namespace lptn::dbc::internal {
namespace {

bool is_alpha(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_word(char c) { return is_alpha(c) || is_digit(c); }

std::string python_repr(char c) {
  if (c == '\'') return "\"'\"";
  if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7F) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "'\\x%02x'", static_cast<unsigned char>(c));
    return buf;
  }
  return std::string("'") + c + "'";
}

// The longest number at `pos` (digits[.digits]|.digits, then an optional exponent), or 0.
std::size_t number_length(std::string_view t, std::size_t pos) {
  std::size_t p = pos;
  const auto digits = [&] {
    const std::size_t from = p;
    while (p < t.size() && is_digit(t[p])) ++p;
    return p - from;
  };
  if (digits() > 0) {
    if (p < t.size() && t[p] == '.') {
      ++p;
      digits();
    }
  } else if (p < t.size() && t[p] == '.') {
    ++p;
    if (digits() == 0) return 0;
  } else {
    return 0;
  }
  if (p < t.size() && (t[p] == 'e' || t[p] == 'E')) {
    std::size_t q = p + 1;
    if (q < t.size() && (t[q] == '+' || t[q] == '-')) ++q;
    const std::size_t first = q;
    while (q < t.size() && is_digit(t[q])) ++q;
    if (q > first) p = q;
  }
  // Any shorter match would be followed by a digit, '.' or a letter, which the pattern refuses too.
  if (p < t.size() && (is_word(t[p]) || t[p] == '.')) return 0;
  return p - pos;
}

std::size_t ident_length(std::string_view t, std::size_t pos) {
  std::size_t p = pos;
  if (is_digit(t[p])) {
    while (p < t.size() && is_digit(t[p])) ++p;
    if (p >= t.size() || !is_alpha(t[p])) return 0;
  } else if (!is_alpha(t[p])) {
    return 0;
  }
  while (p < t.size() && is_word(t[p])) ++p;
  return p - pos;
}

const std::set<std::string_view> kSkipped = {
    "BA_DEF_REL_", "BA_REL_", "BA_DEF_DEF_REL_", "BA_DEF_SGTYPE_", "BA_SGTYPE_", "SIG_GROUP_",
    "SIGTYPE_VALTYPE_", "SIG_TYPE_REF_", "EV_", "EV_DATA_", "ENVVAR_DATA_", "SGTYPE_",
    "SGTYPE_VAL_", "CAT_DEF_", "CAT_", "FILTER", "BU_SG_REL_", "BU_EV_REL_", "BU_BO_REL_",
    "NS_DESC_"};
const std::set<std::string_view> kSections = {
    "VERSION", "NS_", "BS_", "BU_", "BO_", "SG_", "CM_", "BA_DEF_", "BA_DEF_DEF_", "BA_", "VAL_",
    "VAL_TABLE_", "SIG_VALTYPE_", "BO_TX_BU_", "SG_MUL_VAL_"};
const std::set<std::string_view> kObjectKinds = {"BU_", "BO_", "SG_", "EV_"};

std::string describe(const Token& t) {
  if (t.kind == Token::Kind::eof) return "end of file";
  if (t.kind == Token::Kind::string) return "a string";
  return "'" + t.text + "'";
}

Statement statement(Statement::Kind kind, int line) {
  Statement st{};
  st.kind = kind;
  st.line = line;
  return st;
}

class Parser {
 public:
  explicit Parser(const std::vector<Token>& tokens) : tokens_(tokens) {}

  Document run() {
    for (;;) {
      const Token& token = take();
      if (token.kind == Token::Kind::eof) break;
      if (token.kind != Token::Kind::ident) fail(token, "a section keyword such as BO_ or CM_");
      if (token.text != "SG_") message_ = nullptr;
      const std::string& k = token.text;
      if (k == "VERSION") string("a version string after VERSION");
      else if (k == "NS_") new_symbols();
      else if (k == "BS_") bit_timing();
      else if (k == "BU_") nodes(token);
      else if (k == "BO_") message_def(token);
      else if (k == "SG_") signal_def(token);
      else if (k == "CM_") comment(token);
      else if (k == "BA_DEF_") attribute_def(token);
      else if (k == "BA_DEF_DEF_") attribute_default(token);
      else if (k == "BA_") attribute_value(token);
      else if (k == "VAL_") value_descriptions(token);
      else if (k == "VAL_TABLE_") value_table(token);
      else if (k == "SIG_VALTYPE_") value_type(token);
      else if (k == "BO_TX_BU_") transmitters(token);
      else if (k == "SG_MUL_VAL_") multiplexing(token);
      else if (kSkipped.count(k)) skip(token);
      else throw ParseError{token.line, "unknown section '" + k + "'"};
    }
    return std::move(doc_);
  }

 private:
  const Token& peek() const { return tokens_[pos_]; }
  const Token& take() {
    const Token& t = tokens_[pos_];
    if (t.kind != Token::Kind::eof) ++pos_;
    return t;
  }
  [[noreturn]] void fail(const Token& t, const std::string& expected) {
    throw ParseError{t.line, "expected " + expected + ", found " + describe(t)};
  }
  bool at_punct(char c) const { return peek().kind == Token::Kind::punct && peek().text[0] == c; }
  bool accept_punct(char c) {
    if (!at_punct(c)) return false;
    take();
    return true;
  }
  int previous_line() const { return pos_ ? tokens_[pos_ - 1].line : peek().line; }
  void punct(char c, const std::string& context) {
    if (accept_punct(c)) return;
    throw ParseError{previous_line(), std::string("expected '") + c + "' " + context + ", found " + describe(peek())};
  }
  std::string ident(const std::string& what) {
    const Token& t = take();
    if (t.kind != Token::Kind::ident) fail(t, what);
    return t.text;
  }
  std::string string(const std::string& what) {
    const Token& t = take();
    if (t.kind != Token::Kind::string) fail(t, what);
    std::string s;
    const std::string_view body = std::string_view(t.text).substr(1, t.text.size() - 2);
    for (std::size_t i = 0; i < body.size(); ++i) {
      if (body[i] == '\\' && i + 1 < body.size() && (body[i + 1] == '"' || body[i + 1] == '\\')) ++i;
      s += body[i];
    }
    return s;
  }
  Number number(const std::string& what) {
    std::string sign;
    if (at_punct('-') || at_punct('+')) sign = take().text;
    const Token& t = take();
    if (t.kind != Token::Kind::number) fail(t, what);
    Number n;
    n.text = sign + t.text;
    if (n.text.size() > 300) throw ParseError{t.line, "number " + n.text.substr(0, 20) + " is out of range"};
    const auto e = n.text.find_first_of("eE");
    if (e != std::string::npos && std::abs(std::atol(n.text.c_str() + e + 1)) > 300)
      throw ParseError{t.line, "number " + n.text.substr(0, 20) + " is out of range"};
    n.value = std::strtod(n.text.c_str(), nullptr);
    if (std::fabs(n.value) > 1e300) throw ParseError{t.line, "number " + n.text + " is out of range"};
    // Whole: no '.', and the exponent leaves no fraction (12, 1e+09; not 15e-1).
    if (n.text.find('.') == std::string::npos) {
      const std::string mantissa = n.text.substr(0, e);
      const long exponent = e == std::string::npos ? 0 : std::atol(n.text.c_str() + e + 1);
      std::size_t trailing_zeros = 0;
      for (auto it = mantissa.rbegin(); it != mantissa.rend() && *it == '0'; ++it) ++trailing_zeros;
      const bool zero = mantissa.find_first_not_of("+-0") == std::string::npos;
      n.whole = zero || exponent >= 0 || static_cast<std::size_t>(-exponent) <= trailing_zeros;
      if (n.whole && std::fabs(n.value) < 9.2e18) n.integer = std::llround(n.value);
      if (n.whole && e == std::string::npos) {
        errno = 0;
        const long long v = std::strtoll(n.text.c_str(), nullptr, 10);
        if (errno == 0) n.integer = v;
      }
    }
    return n;
  }
  long long integer(const std::string& what) {
    const Token& start = peek();
    const Number n = number(what);
    if (!n.whole) fail(start, what);
    return n.integer;
  }
  std::uint64_t natural(const std::string& what) {
    if (at_punct('-') || at_punct('+')) fail(peek(), what);
    const Token& start = peek();
    const Number n = number(what);
    if (!n.whole || start.text.find_first_not_of("0123456789") != std::string::npos) fail(start, what);
    if (start.text.size() > 19) return ~std::uint64_t{0};  // too big for anything: the caller refuses it
    return std::strtoull(start.text.c_str(), nullptr, 10);
  }
  Value value(const std::string& what) {
    if (peek().kind == Token::Kind::string) return string(what);
    return number(what);
  }
  bool at_next_section() const {
    const Token& t = peek();
    const Token& previous = pos_ ? tokens_[pos_ - 1] : t;
    return t.kind == Token::Kind::eof || (t.kind == Token::Kind::ident && t.line > previous.line &&
                                          (kSections.count(t.text) || kSkipped.count(t.text)));
  }
  bool missing_semicolon(const std::string& section) {
    if (!at_next_section()) return false;
    doc_.warnings.emplace_back(previous_line(), "expected ';' at the end of " + section + ", found " + describe(peek()) +
                                                    "; read as if it were there");
    return true;
  }
  void end(const std::string& section) {
    if (!at_punct(';') && missing_semicolon(section)) return;
    punct(';', "at the end of " + section);
  }
  void skip(const Token& keyword) {
    while (!accept_punct(';'))
      if (take().kind == Token::Kind::eof) throw ParseError{keyword.line, keyword.text + " has no ';' at its end"};
  }

  void new_symbols() {
    punct(':', "after NS_");
    while (peek().kind == Token::Kind::ident && peek().text != "BS_" && peek().text != "BU_") take();
  }
  void bit_timing() {
    punct(':', "after BS_");
    if (peek().kind == Token::Kind::number) {
      integer("a baud rate");
      punct(':', "after the baud rate");
      integer("BTR1");
      punct(',', "between BTR1 and BTR2");
      integer("BTR2");
    }
  }
  void nodes(const Token& keyword) {
    if (doc_.nodes_line)
      throw ParseError{keyword.line, "second BU_ section (the first is on line " + std::to_string(*doc_.nodes_line) + ")"};
    doc_.nodes_line = keyword.line;
    punct(':', "after BU_");
    while (peek().kind == Token::Kind::ident && !kSections.count(peek().text) && !kSkipped.count(peek().text)) {
      const Token& t = take();
      doc_.nodes.emplace_back(t.text, t.line);
    }
  }
  void message_def(const Token& keyword) {
    const std::uint64_t id = natural("a message id after BO_");
    if (id >= (std::uint64_t{1} << 32))
      throw ParseError{keyword.line, "message id " + std::to_string(id) + " does not fit in 32 bits"};
    RawMessage m;
    m.dbc_id = id;
    m.name = ident("a message name");
    punct(':', "after the message name");
    m.dlc = static_cast<long long>(natural("the message length (DLC)"));
    m.sender = ident("the sending node");
    m.line = keyword.line;
    doc_.messages.push_back(std::move(m));
    message_ = &doc_.messages.back();
  }
  void signal_def(const Token& keyword) {
    if (!message_) throw ParseError{keyword.line, "SG_ must follow its message's BO_ line"};
    RawSignal r;
    Signal& s = r.signal;
    s.line = keyword.line;
    s.name = ident("a signal name after SG_");
    if (peek().kind == Token::Kind::ident) {  // the multiplex indicator: M, m<N> or m<N>M
      const std::string indicator = take().text;
      std::size_t digits = 0;
      while (1 + digits < indicator.size() && is_digit(indicator[1 + digits])) ++digits;
      const bool m_n = indicator.size() > 1 && indicator[0] == 'm' && digits > 0 &&
                       (1 + digits == indicator.size() || (2 + digits == indicator.size() && indicator.back() == 'M'));
      if (indicator == "M") {
        s.mux = Signal::Mux::multiplexor;
      } else if (m_n && indicator.back() == 'M') {
        throw ParseError{keyword.line, "signal " + s.name + ": extended multiplexing (" + indicator +
                                           ": a multiplexed multiplexor) is not supported, only one multiplexor per message"};
      } else if (m_n) {
        s.mux = Signal::Mux::multiplexed;
        s.mux_value = std::strtoll(indicator.c_str() + 1, nullptr, 10);
        s.mux_ranges = {{s.mux_value, s.mux_value}};
      } else if (indicator == "m") {
        s.mux = Signal::Mux::multiplexor;
        doc_.warnings.emplace_back(keyword.line, "signal " + s.name +
                                                     ": multiplex indicator 'm' without a value; read as 'M' (the multiplexor)");
      } else {
        throw ParseError{keyword.line, "signal " + s.name + ": expected ':' or a multiplex indicator (M or m<N>), found '" +
                                           indicator + "'"};
      }
    }
    punct(':', "after the signal name");
    const std::uint64_t start = natural("the start bit");
    punct('|', "between start bit and length");
    const std::uint64_t length = natural("the signal length");
    punct('@', "before the byte order");
    const Token& order_token = peek();
    const std::uint64_t order = natural("the byte order (0 or 1)");
    if (order > 1) fail(order_token, "the byte order 0 (Motorola) or 1 (Intel)");
    const Token& sign = take();
    if (sign.kind != Token::Kind::punct || (sign.text != "+" && sign.text != "-"))
      fail(sign, "'+' (unsigned) or '-' (signed) after the byte order");
    punct('(', "before the factor");
    r.factor = number("the factor");
    punct(',', "between factor and offset");
    r.offset = number("the offset");
    punct(')', "after the offset");
    punct('[', "before the minimum");
    r.minimum = number("the minimum");
    punct('|', "between minimum and maximum");
    r.maximum = number("the maximum");
    punct(']', "after the maximum");
    s.factor = r.factor.value;
    s.offset = r.offset.value;
    s.minimum = r.minimum.value;
    s.maximum = r.maximum.value;
    s.factor_text = r.factor.text;
    s.offset_text = r.offset.text;
    s.minimum_text = r.minimum.text;
    s.maximum_text = r.maximum.text;
    s.unit = string("the unit string");
    s.receivers.push_back(ident("a receiving node"));
    while (accept_punct(',')) s.receivers.push_back(ident("a receiving node after ','"));
    // Positions beyond any frame are caught by the overflow check; clamp so the int fields hold them.
    s.start = static_cast<int>(std::min<std::uint64_t>(start, 1u << 20));
    s.length = static_cast<int>(std::min<std::uint64_t>(length, 1u << 20));
    s.big_endian = order == 0;
    s.is_signed = sign.text == "-";
    message_->signals.push_back(std::move(r));
  }
  // `BU_ node`, `BO_ id`, `SG_ id signal` or `EV_ name`, or nothing (the network).
  void object_ref(Statement& st) {
    if (peek().kind != Token::Kind::ident || !kObjectKinds.count(peek().text)) return;
    st.object_kind = take().text;
    if (st.object_kind == "BO_") {
      st.message_id = static_cast<std::uint64_t>(integer("a message id"));
    } else if (st.object_kind == "SG_") {
      st.message_id = static_cast<std::uint64_t>(integer("a message id"));
      st.signal = ident("a signal name");
    } else {
      st.signal = ident(st.object_kind == "BU_" ? "a node name" : "an environment variable");
    }
  }
  void comment(const Token& keyword) {
    Statement st = statement(Statement::Kind::comment, keyword.line);
    object_ref(st);
    st.text = string("the comment string");
    end("CM_");
    doc_.statements.push_back(std::move(st));
  }
  void attribute_def(const Token& keyword) {
    AttributeDef d;
    d.line = keyword.line;
    if (kObjectKinds.count(peek().text)) d.object_kind = take().text;
    const std::string name = string("the attribute name");
    if (auto it = doc_.attribute_defs.find(name); it != doc_.attribute_defs.end())
      throw ParseError{keyword.line, "attribute \"" + name + "\" is already defined on line " + std::to_string(it->second.line)};
    const Token& type_token = peek();
    d.type = ident("an attribute type");
    if (d.type == "INT" || d.type == "HEX") {
      const Token& a = peek();
      d.minimum = number("the minimum");
      if (!d.minimum.whole) fail(a, "the minimum");
      const Token& b = peek();
      d.maximum = number("the maximum");
      if (!d.maximum.whole) fail(b, "the maximum");
    } else if (d.type == "FLOAT") {
      d.minimum = number("the minimum");
      d.maximum = number("the maximum");
    } else if (d.type == "ENUM") {
      d.choices.push_back(string("an enum value"));
      while (accept_punct(',')) d.choices.push_back(string("an enum value after ','"));
    } else if (d.type != "STRING") {
      fail(type_token, "an attribute type (INT, HEX, FLOAT, STRING or ENUM)");
    }
    end("BA_DEF_");
    doc_.attribute_defs.emplace(name, std::move(d));
  }
  void attribute_default(const Token& keyword) {
    Statement st = statement(Statement::Kind::attr_default, keyword.line);
    st.name = string("the attribute name");
    st.value = value("the default value");
    end("BA_DEF_DEF_");
    doc_.statements.push_back(std::move(st));
  }
  void attribute_value(const Token& keyword) {
    Statement st = statement(Statement::Kind::attr_value, keyword.line);
    st.name = string("the attribute name");
    object_ref(st);
    st.value = value("the attribute value");
    end("BA_");
    doc_.statements.push_back(std::move(st));
  }
  std::vector<std::pair<long long, std::string>> value_pairs(const std::string& section) {
    std::vector<std::pair<long long, std::string>> pairs;
    std::set<long long> seen;
    while (!accept_punct(';')) {
      if (!pairs.empty() && missing_semicolon(section)) break;
      const Token& t = peek();
      const long long raw = integer("a raw value or the ';' that ends " + section);
      if (!seen.insert(raw).second) throw ParseError{t.line, "value " + std::to_string(raw) + " is described twice"};
      pairs.emplace_back(raw, string("the value's description"));
    }
    return pairs;
  }
  void value_descriptions(const Token& keyword) {
    if (peek().kind == Token::Kind::ident) {  // an environment variable's: not a frame's business
      take();
      value_pairs("VAL_");
      return;
    }
    Statement st = statement(Statement::Kind::values, keyword.line);
    st.message_id = static_cast<std::uint64_t>(integer("a message id or environment variable after VAL_"));
    st.signal = ident("a signal name");
    st.pairs = value_pairs("VAL_");
    doc_.statements.push_back(std::move(st));
  }
  void value_table(const Token& keyword) {
    const std::string name = ident("a value table name");
    if (!value_tables_.insert(name).second) throw ParseError{keyword.line, "value table " + name + " is defined twice"};
    value_pairs("VAL_TABLE_");
  }
  void value_type(const Token& keyword) {
    Statement st = statement(Statement::Kind::value_type, keyword.line);
    st.message_id = static_cast<std::uint64_t>(integer("a message id after SIG_VALTYPE_"));
    st.signal = ident("a signal name");
    accept_punct(':');
    st.value_type = integer("the value type (0 integer, 1 float, 2 double)");
    end("SIG_VALTYPE_");
    doc_.statements.push_back(std::move(st));
  }
  void transmitters(const Token& keyword) {
    Statement st = statement(Statement::Kind::transmitters, keyword.line);
    st.message_id = static_cast<std::uint64_t>(integer("a message id after BO_TX_BU_"));
    punct(':', "after the message id");
    st.nodes.push_back(ident("a node name"));
    while (accept_punct(',')) st.nodes.push_back(ident("a node name after ','"));
    end("BO_TX_BU_");
    doc_.statements.push_back(std::move(st));
  }
  void multiplexing(const Token& keyword) {
    Statement st = statement(Statement::Kind::mux_values, keyword.line);
    st.message_id = static_cast<std::uint64_t>(integer("a message id after SG_MUL_VAL_"));
    st.signal = ident("a signal name");
    st.multiplexor = ident("the multiplexor's name");
    for (;;) {
      const auto low = static_cast<long long>(natural("the low end of a multiplexor value range"));
      punct('-', "between the ends of a multiplexor value range");
      const auto high = static_cast<long long>(natural("the high end of a multiplexor value range"));
      if (low > high)
        throw ParseError{keyword.line, "multiplexor value range " + std::to_string(low) + "-" + std::to_string(high) + " is empty"};
      st.ranges.emplace_back(low, high);
      if (!accept_punct(',')) break;
    }
    end("SG_MUL_VAL_");
    doc_.statements.push_back(std::move(st));
  }

  const std::vector<Token>& tokens_;
  std::size_t pos_ = 0;
  Document doc_;
  RawMessage* message_ = nullptr;  // the BO_ that SG_ lines belong to: the last message, re-taken after each
                                   // push_back
  std::set<std::string> value_tables_;
};

}  // namespace

std::vector<Token> tokenize(std::string_view t) {
  std::vector<Token> tokens;
  int line = 1;
  std::size_t pos = 0;
  while (pos < t.size()) {
    const char c = t[pos];
    if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
      ++pos;
    } else if (c == '\n') {
      ++line;
      ++pos;
    } else if (c == '"') {
      std::size_t p = pos + 1;
      int lines = 0;
      while (p < t.size() && t[p] != '"') {
        if (t[p] == '\\' && p + 1 < t.size()) ++p;  // an escaped character, whatever it is
        if (t[p] == '\n') ++lines;
        ++p;
      }
      if (p >= t.size()) throw ParseError{line, "unterminated string"};
      tokens.push_back({Token::Kind::string, std::string(t.substr(pos, p + 1 - pos)), line});
      line += lines;
      pos = p + 1;
    } else if (const std::size_t n = number_length(t, pos)) {
      tokens.push_back({Token::Kind::number, std::string(t.substr(pos, n)), line});
      pos += n;
    } else if (const std::size_t i = ident_length(t, pos)) {
      tokens.push_back({Token::Kind::ident, std::string(t.substr(pos, i)), line});
      pos += i;
    } else if (std::string_view(":;|@(),[]+-").find(c) != std::string_view::npos) {
      tokens.push_back({Token::Kind::punct, std::string(1, c), line});
      ++pos;
    } else {
      throw ParseError{line, "unexpected character " + python_repr(c)};
    }
  }
  tokens.push_back({Token::Kind::eof, "", line});
  return tokens;
}

Document parse_document(const std::vector<Token>& tokens) { return Parser(tokens).run(); }

}  // namespace lptn::dbc::internal
