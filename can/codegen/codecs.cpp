// The header's text, line by line as the Python generator it replaced wrote it: on every DBC of the
// tree the two wrote the same bytes but the first line, which names the generator.
#include "can/codegen/codecs.hpp"

#include <algorithm>
#include <cmath>

#include "can/codegen/cxx_names.hpp"
#include "can/codegen/cxx_text.hpp"

namespace lptn::codegen {
namespace {

using dbc::Message;
using dbc::Signal;
using Lines = std::vector<std::string>;

void append(Lines& to, const Lines& more) { to.insert(to.end(), more.begin(), more.end()); }
std::string join(const Lines& parts, const std::string& separator) {
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? separator : "") + parts[i];
  return out;
}

int width_of(const Signal& s) { return s.length <= 8 ? 8 : s.length <= 16 ? 16 : s.length <= 32 ? 32 : 64; }
std::string cxx_type(const Signal& s) { return std::string("std::") + (s.is_signed ? "" : "u") + "int" + std::to_string(width_of(s)) + "_t"; }
std::string unsigned_type(const Signal& s) { return "std::uint" + std::to_string(width_of(s)) + "_t"; }

// What `bits` bits hold, and what a type of `bits` bits holds: exact as long doubles up to 2^64.
std::pair<long double, long double> limits(int bits, bool is_signed) {
  const long double span = static_cast<long double>(std::uint64_t{1} << (bits - 1)) * 2.0L;
  return is_signed ? std::pair{-span / 2, span / 2 - 1} : std::pair{0.0L, span - 1};
}
std::string literal(long double whole, bool is_signed) {
  return is_signed ? int_literal(static_cast<std::int64_t>(whole), true) : uint_literal(static_cast<std::uint64_t>(whole));
}

std::vector<int> frame_bits(const Signal& s) {
  std::vector<int> bits;
  if (!s.big_endian) {
    for (int i = 0; i < s.length; ++i) bits.push_back(s.start + i);
    return bits;
  }
  // Motorola: the start bit is the MSB; DBC numbers bits in a sawtooth, so after bit 0 of a byte the
  // signal continues at bit 7 of the next byte.
  int position = s.start;
  for (int i = 0; i < s.length; ++i) {
    bits.push_back(position);
    position = position % 8 == 0 ? position + 15 : position - 1;
  }
  std::reverse(bits.begin(), bits.end());
  return bits;
}

// Bits [low, low + width) of frame byte `byte` hold value bits [shift, shift + width).
struct Chunk {
  int byte, low, width, shift;
};
std::vector<Chunk> chunks(const Signal& s) {
  std::vector<Chunk> out;
  const std::vector<int> bits = frame_bits(s);
  for (int value_bit = 0; value_bit < static_cast<int>(bits.size()); ++value_bit) {
    const int byte = bits[static_cast<std::size_t>(value_bit)] / 8, low = bits[static_cast<std::size_t>(value_bit)] % 8;
    if (!out.empty() && out.back().byte == byte && out.back().low + out.back().width == low)
      ++out.back().width;
    else
      out.push_back({byte, low, 1, value_bit});
  }
  std::stable_sort(out.begin(), out.end(), [](const Chunk& a, const Chunk& b) { return a.byte < b.byte; });
  return out;
}

std::string format_ranges(const std::vector<std::pair<std::int64_t, std::int64_t>>& ranges) {
  Lines parts;
  for (const auto& [low, high] : ranges) parts.push_back(low == high ? std::to_string(low) : std::to_string(low) + ".." + std::to_string(high));
  return join(parts, ", ");
}

// The SG_ definition as the DBC writes it, for the reader who checks against the file.
std::string sg_notation(const Signal& s) {
  return std::to_string(s.start) + "|" + std::to_string(s.length) + "@" + (s.big_endian ? "0" : "1") + (s.is_signed ? "-" : "+") + " (" +
         s.factor_text + "," + s.offset_text + ") [" + s.minimum_text + "|" + s.maximum_text + "] " + string_literal(s.unit);
}

Lines indented(const Lines& lines) {
  Lines out;
  for (const std::string& l : lines) out.push_back(l.empty() ? l : "  " + l);
  return out;
}

// dst[byte] |= the value bits that byte holds: one line per byte the signal touches.
Lines pack_lines(const Signal& s, const SignalNames& n) {
  Lines lines{"    // " + s.name + " " + sg_notation(s)};
  std::string source = n.member, indent = "    ";
  if (s.is_signed) {  // shift and mask the two's complement bits, not a negative number
    lines.push_back("    {");
    lines.push_back("      const auto bits = static_cast<" + unsigned_type(s) + ">(" + source + ");");
    source = "bits";
    indent = "      ";
  }
  for (const Chunk& c : chunks(s)) {
    const std::string value = c.shift ? "(" + source + " >> " + std::to_string(c.shift) + ")" : source;
    std::string term = "(" + value + " & " + hex_mask(c.width) + ")";
    if (c.low) term = "(" + term + " << " + std::to_string(c.low) + ")";
    const std::string byte = std::to_string(c.byte);
    lines.push_back(indent + "dst[" + byte + "] = static_cast<std::uint8_t>(dst[" + byte + "] | " + term + ");");
  }
  if (s.is_signed) lines.push_back("    }");
  return lines;
}

struct Term {
  std::string text;
  bool single;  // one operand: needs no parentheses
};
std::string operand(const Term& t) { return t.single ? t.text : "(" + t.text + ")"; }

// The value bits each byte of src[] holds, moved to their place in the raw value. Below 32 bits the
// terms are plain ints (a byte shifted by up to 23 bits fits); from 32 bits on each byte is widened
// to the raw value's unsigned type. Narrow terms are int, or unsigned once masked: mask all or
// none, so that `|` never mixes signedness (clang's -Wsign-conversion).
std::vector<Term> gather_terms(const Signal& s) {
  const bool wide = width_of(s) >= 32;
  const std::vector<Chunk> cs = chunks(s);
  const bool mask_all = !wide && std::any_of(cs.begin(), cs.end(), [](const Chunk& c) { return c.width < 8; });
  std::vector<Term> terms;
  for (const Chunk& c : cs) {
    Term t{"src[" + std::to_string(c.byte) + "]", true};
    if (c.low) t = {t.text + " >> " + std::to_string(c.low), false};
    if (c.width < 8 || mask_all) t = {operand(t) + " & " + hex_mask(c.width), false};
    if (wide) t = {"static_cast<" + unsigned_type(s) + ">(" + t.text + ")", true};
    if (c.shift) t = {operand(t) + " << " + std::to_string(c.shift), false};
    terms.push_back(t);
  }
  return terms;
}

// The signal's bits from src[] as a type_name, to follow `prefix` on its line; one byte per line if
// the statement would not fit in 100 columns.
std::string gather_expression(const Signal& s, const std::string& type_name, const std::string& prefix) {
  const std::vector<Term> terms = gather_terms(s);
  if (terms.size() == 1) return "static_cast<" + type_name + ">(" + terms[0].text + ")";
  Lines operands;
  for (const Term& t : terms) operands.push_back(operand(t));
  std::string opening, closing;
  if (!(width_of(s) >= 32 && type_name == unsigned_type(s))) {  // else the terms are of that type already
    opening = "static_cast<" + type_name + ">(";
    closing = ")";
  }
  const std::string one_line = opening + join(operands, " | ") + closing;
  if (prefix.size() + one_line.size() + 1 <= 100) return one_line;
  const std::string indent = prefix.substr(0, prefix.find_first_not_of(' '));
  const std::string first_break = opening.empty() ? "" : "\n" + indent + "    ";
  return opening + first_break + join(operands, " |\n" + indent + "    ") + closing;
}

Lines unpack_lines(const Signal& s, const SignalNames& n) {
  const int width = width_of(s);
  Lines lines{"    // " + s.name + " " + sg_notation(s)};
  if (!s.is_signed || s.length == width) {
    // A full-width signed value converts modulo 2^width: the bits are its two's complement.
    const std::string prefix = "    " + n.member + " = ";
    lines.push_back(prefix + gather_expression(s, cxx_type(s), prefix) + ";");
  } else {
    const std::uint64_t sign_bit = std::uint64_t{1} << (s.length - 1);
    const std::uint64_t type_mask = width == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << width) - 1;
    const std::uint64_t above = type_mask ^ ((std::uint64_t{1} << s.length) - 1);
    const std::string prefix = "      const auto bits = ";
    lines.push_back("    {");
    lines.push_back(prefix + gather_expression(s, unsigned_type(s), prefix) + ";");
    lines.push_back("      // sign-extend: bit " + std::to_string(s.length - 1) + " is the sign, so copy it into the bits above");
    lines.push_back("      " + n.member + " = static_cast<" + cxx_type(s) + ">((bits & 0x" + hex_upper(sign_bit) + "u) != 0 ? bits | 0x" +
                    hex_upper(above) + "u : bits);");
    lines.push_back("    }");
  }
  return lines;
}

std::string decode_expression(const Signal& s) {
  std::string e = "static_cast<double>(raw)";
  if (dbc::compare_exact(s.factor_text, 1) != 0) e += " * " + shortest_double(s.factor);
  if (const int sign = dbc::compare_exact(s.offset_text, 0); sign != 0)
    e += std::string(sign > 0 ? " + " : " - ") + shortest_double(std::abs(s.offset));
  return e;
}

std::string encode_expression(const Signal& s) {
  std::string scaled = "value";
  if (const int sign = dbc::compare_exact(s.offset_text, 0); sign != 0)
    scaled = std::string("(value ") + (sign > 0 ? "-" : "+") + " " + shortest_double(std::abs(s.offset)) + ")";
  if (dbc::compare_exact(s.factor_text, 1) != 0) scaled += " / " + shortest_double(s.factor);
  const auto [low, high] = limits(s.length, s.is_signed);
  const std::string call = s.is_signed ? "detail::round_saturate_i64(" + scaled + ", " + literal(low, true) + ", " + literal(high, true) + ")"
                                       : "detail::round_saturate_u64(" + scaled + ", " + literal(high, false) + ")";
  return width_of(s) == 64 ? call : "static_cast<" + cxx_type(s) + ">(" + call + ")";
}

// Comparisons of the raw value against the DBC range (exact, done by the reader), leaving out those
// the raw type makes always true (-Wtype-limits).
Lines in_range_conditions(const Signal& s) {
  if (!s.raw_range) return {};
  const auto [type_low, type_high] = limits(width_of(s), s.is_signed);
  Lines conditions;
  if (s.raw_range->low > type_low) conditions.push_back("raw >= " + literal(s.raw_range->low, s.is_signed));
  if (s.raw_range->high < type_high) conditions.push_back("raw <= " + literal(s.raw_range->high, s.is_signed));
  return conditions;
}

// `return expression;`, broken after the outer cast's parenthesis if longer than 100 columns.
Lines return_lines(const std::string& expression) {
  const std::string line = "    return " + expression + ";";
  if (line.size() <= 100 || expression.rfind("static_cast<", 0) != 0) return {line};
  const std::size_t paren = expression.find('(');
  return {"    return " + expression.substr(0, paren) + "(", "        " + expression.substr(paren + 1) + ";"};
}

Lines signal_function_lines(const Signal& s, const SignalNames& n) {
  const std::string type = cxx_type(s);
  const std::string unit = s.unit.empty() ? "" : " " + ascii_text(s.unit);
  std::string offset = s.offset_text;
  offset.erase(0, offset.find_first_not_of("+-"));
  const Lines conditions = in_range_conditions(s);
  const std::string parameter = conditions.empty() ? "/*raw*/" : "raw";
  const std::string body = conditions.empty() ? "true" : join(conditions, " && ");
  Lines lines{"  // " + s.name + ": raw * " + s.factor_text + " " + (dbc::compare_exact(s.offset_text, 0) < 0 ? "-" : "+") +
                  " " + offset + unit + ", in range [" + s.minimum_text + "|" + s.maximum_text + "]" +
                  (s.range_ignored ? " (ignored: it cannot be right)" : ""),
              "  static constexpr double " + n.base + "_decode(" + type + " raw) noexcept {",
              "    return " + decode_expression(s) + ";",
              "  }",
              "  static constexpr " + type + " " + n.base + "_encode(double value) noexcept {"};
  append(lines, return_lines(encode_expression(s)));
  append(lines, {"  }", "  static constexpr bool " + n.base + "_is_in_range(" + type + " " + parameter + ") noexcept {",
                 "    return " + body + ";", "  }"});
  return lines;
}

Lines enum_lines(const Signal& s, const SignalNames& n) {
  Lines items;
  for (std::size_t i = 0; i < s.values.size(); ++i) items.push_back(n.enumerators[i] + " = " + int_literal(s.values[i].first, true));
  const std::string head = "  enum class " + n.enum_name + " : " + cxx_type(s) + " {";
  const std::string one_line = head + " " + join(items, ", ") + " };";
  if (one_line.size() <= 100) return {one_line};
  Lines lines{head};
  for (const std::string& item : items) lines.push_back("    " + item + ",");
  lines.push_back("  };");
  return lines;
}

std::string signal_info(const Signal& s) {
  return "{" + string_literal(s.name) + ", " + string_literal(s.unit) + ", " + shortest_double(s.factor) + ", " + shortest_double(s.offset) +
         ", " + shortest_double(s.minimum) + ", " + shortest_double(s.maximum) + ", " + std::to_string(s.start) + ", " +
         std::to_string(s.length) + ", " + (s.is_signed ? "true" : "false") + ", " + (s.big_endian ? "true" : "false") + "}";
}

// The condition under which the frame carries a multiplexed signal, comparing the multiplexor's raw
// member only where its type does not make the comparison constant.
std::string present_condition(const Signal& s, const Signal& mux, const std::string& mux_member) {
  const auto [type_low, type_high] = limits(width_of(mux), mux.is_signed);
  const auto [raw_low, raw_high] = limits(mux.length, mux.is_signed);
  Lines alternatives;
  for (const auto& [range_low, range_high] : s.mux_ranges) {
    const long double low = std::max(static_cast<long double>(range_low), raw_low);
    const long double high = std::min(static_cast<long double>(range_high), raw_high);
    if (low > high) continue;
    if (low == high) {
      alternatives.push_back(mux_member + " == " + literal(low, mux.is_signed));
      continue;
    }
    Lines ends;
    if (low > type_low) ends.push_back(mux_member + " >= " + literal(low, mux.is_signed));
    if (high < type_high) ends.push_back(mux_member + " <= " + literal(high, mux.is_signed));
    if (ends.empty()) return "true";
    alternatives.push_back(join(ends, " && "));
  }
  if (alternatives.empty()) return "false";
  if (alternatives.size() == 1) return alternatives[0];
  for (std::string& a : alternatives)
    if (a.find("&&") != std::string::npos) a = "(" + a + ")";
  return join(alternatives, " || ");
}

Lines message_lines(const Message& m, const MessageNames& names) {
  const std::string cycle = m.cycle_ms ? "every " + std::to_string(m.cycle_ms) + " ms" : "no cycle time";
  Lines lines = comment_lines(m.name + ": id 0x" + hex_upper(m.id) + (m.extended ? " (extended)" : "") + ", " + std::to_string(m.length) +
                                  " bytes, " + cycle + ", sent by " + m.sender + ".",
                              "");
  if (!m.comment.empty()) append(lines, comment_lines(m.comment, ""));
  const Signal* mux = m.multiplexor();
  std::string mux_member;
  if (mux) {
    append(lines, comment_lines("Multiplexed: " + mux->name +
                                    " says which of the signals marked m<N> the frame carries. unpack() reads those it carries and "
                                    "zeroes the others; pack() writes those the multiplexor's value selects; NAME_is_present() tells which.",
                                ""));
    for (std::size_t i = 0; i < m.signals.size(); ++i)
      if (&m.signals[i] == mux) mux_member = names.signals[i].member;
  }
  append(lines, {"struct " + names.type + " {", "  static constexpr std::uint32_t kId = 0x" + hex_upper(m.id) + ";",
                 std::string("  static constexpr bool kExtended = ") + (m.extended ? "true" : "false") + ";",
                 "  static constexpr std::uint8_t kLength = " + std::to_string(m.length) + ";",
                 "  static constexpr std::uint32_t kCycleTimeMs = " + std::to_string(m.cycle_ms) + ";",
                 "  static constexpr const char* kName = " + string_literal(m.name) + ";",
                 "  static constexpr const char* kSender = " + string_literal(m.sender) + ";"});
  const std::size_t count = m.signals.size();
  for (std::size_t i = 0; i < count; ++i)
    if (!m.signals[i].values.empty()) {
      lines.push_back("");
      append(lines, comment_lines("Values of " + m.signals[i].name + " (VAL_).", "  "));
      append(lines, enum_lines(m.signals[i], names.signals[i]));
    }
  if (count) append(lines, {"", "  // Raw signal values, the bits on the wire: physical = raw * factor + offset."});
  std::vector<std::size_t> plain, muxed;
  for (std::size_t i = 0; i < count; ++i) {
    const Signal& s = m.signals[i];
    if (!s.comment.empty()) append(lines, comment_lines(s.comment, "  "));
    std::string note;
    if (s.mux == Signal::Mux::multiplexor) note = ", the multiplexor";
    if (s.mux == Signal::Mux::multiplexed) note = ", in the frame when " + mux->name + " is " + format_ranges(s.mux_ranges);
    lines.push_back("  " + cxx_type(s) + " " + names.signals[i].member + " = 0;  // " + sg_notation(s) + note);
    (s.mux == Signal::Mux::multiplexed ? muxed : plain).push_back(i);
  }
  if (!muxed.empty()) {
    append(lines, {"", "  // Whether the frame carries the signal: " + mux->name + "'s value selects it."});
    for (const std::size_t i : muxed)
      append(lines, {"  constexpr bool " + names.signals[i].base + "_is_present() const noexcept {",
                     "    return " + present_condition(m.signals[i], *mux, mux_member) + ";", "  }"});
  }
  if (m.length == 0) {
    append(lines, {"", "  // A frame without data: nothing to write or read.",
                   "  constexpr bool pack(std::uint8_t* /*dst*/, std::size_t /*size*/) const noexcept { return true; }",
                   "  constexpr bool unpack(const std::uint8_t* /*src*/, std::size_t /*size*/) noexcept { return true; }"});
  } else {
    append(lines, {"", "  // Writes kLength bytes (unused bits 0). false (nothing written) if size < kLength.",
                   "  constexpr bool pack(std::uint8_t* dst, std::size_t size) const noexcept {", "    if (size < kLength) {",
                   "      return false;", "    }", "    for (std::size_t i = 0; i < kLength; ++i) {", "      dst[i] = 0;", "    }"});
    for (const std::size_t i : plain) append(lines, pack_lines(m.signals[i], names.signals[i]));
    for (const std::size_t i : muxed) {
      lines.push_back("    if (" + names.signals[i].base + "_is_present()) {");
      append(lines, indented(pack_lines(m.signals[i], names.signals[i])));
      lines.push_back("    }");
    }
    append(lines, {"    return true;", "  }", "", "  // false (nothing changed) if size < kLength. Signed signals are sign-extended.",
                   std::string("  constexpr bool unpack(const std::uint8_t* ") + (count ? "src" : "/*src*/") +
                       ", std::size_t size) noexcept {",
                   "    if (size < kLength) {", "      return false;", "    }"});
    for (const std::size_t i : plain) append(lines, unpack_lines(m.signals[i], names.signals[i]));
    for (const std::size_t i : muxed) {
      lines.push_back("    if (" + names.signals[i].base + "_is_present()) {");
      append(lines, indented(unpack_lines(m.signals[i], names.signals[i])));
      append(lines, {"    } else {", "      " + names.signals[i].member + " = 0;", "    }"});
    }
    append(lines, {"    return true;", "  }"});
  }
  lines.push_back("");
  if (count)
    append(lines, {"  // encode: round((value - offset) / factor), saturated to what the signal's bits hold; NaN -> 0.",
                   "  // is_in_range: the DBC's [min|max] on the physical value ([0|0]: any raw value)."});
  for (std::size_t i = 0; i < count; ++i) append(lines, signal_function_lines(m.signals[i], names.signals[i]));
  if (count) {
    append(lines, {"", "  // name, unit, factor, offset, min, max, start, length, is_signed, big_endian (DBC order)",
                   "  static constexpr SignalInfo kSignals[] = {"});
    for (const Signal& s : m.signals) lines.push_back("      " + signal_info(s) + ",");
    lines.push_back("  };");
  } else {
    append(lines, {"  // No signals (C++ has no empty arrays): kSignals points nowhere.",
                   "  static constexpr const SignalInfo* kSignals = nullptr;"});
  }
  append(lines, {"  static constexpr std::size_t kNumSignals = " + std::to_string(count) + ";", "};", ""});
  return lines;
}

const char* const kDetail = R"(namespace detail {

// round(x), halves away from zero, saturated to [low, high]; NaN gives 0. Written out because
// std::round is not constexpr before C++23.
constexpr std::int64_t round_saturate_i64(double x, std::int64_t low, std::int64_t high) noexcept {
  if (x > static_cast<double>(low) && x < static_cast<double>(high)) {
    const auto whole = static_cast<std::int64_t>(x);  // truncates toward zero
    const double rest = x - static_cast<double>(whole);
    if (rest >= 0.5) {
      return whole + 1;
    }
    if (rest <= -0.5) {
      return whole - 1;
    }
    return whole;
  }
  if (x >= static_cast<double>(high)) {
    return high;
  }
  if (x <= static_cast<double>(low)) {
    return low;
  }
  return 0;  // NaN: every comparison above was false
}

// The same for unsigned signals: [0, high].
constexpr std::uint64_t round_saturate_u64(double x, std::uint64_t high) noexcept {
  if (x > 0.0 && x < static_cast<double>(high)) {
    const auto whole = static_cast<std::uint64_t>(x);
    return x - static_cast<double>(whole) >= 0.5 ? whole + 1 : whole;
  }
  if (x >= static_cast<double>(high)) {
    return high;
  }
  return 0;  // at or below 0, or NaN
}

}  // namespace detail
)";

Lines id_array_lines(const std::string& name, const Message* const* begin, std::size_t n, const std::vector<std::string>& types) {
  if (n == 0) return {"// " + name + ": none (C++ has no empty arrays, so the array is left out)."};
  Lines lines{"inline constexpr std::uint32_t " + name + "[] = {"};
  for (std::size_t i = 0; i < n; ++i) lines.push_back("    " + types[i] + "::kId,  // 0x" + hex_upper(begin[i]->id));
  lines.push_back("};");
  return lines;
}

}  // namespace

std::string codecs_header(const dbc::Database& db, const CodecsRequest& request, std::vector<dbc::Warning>& warnings) {
  const std::vector<MessageNames> names = cxx_names(db, warnings);
  Lines lines{"// Generated by lptn-dbc-codegen (can/codegen) from " + request.dbc_name + "; do not edit."};
  if (!db.comment.empty()) append(lines, comment_lines(db.comment, ""));
  append(lines, {"#pragma once", "#include <cstddef>", "#include <cstdint>", "", "namespace " + request.ns + " {", "",
                 "// One signal's DBC definition, for code that walks a message's signals (logs, range tables)."});
  // A 16-bit start where a CAN FD frame of more than 32 bytes has start bits above 255 (the classic
  // layout otherwise, as every header had it before CAN FD).
  if (std::all_of(db.messages.begin(), db.messages.end(), [](const Message& m) { return m.length <= 32; })) {
    lines.push_back("struct SignalInfo { const char* name; const char* unit; double factor, offset, min, max; std::uint8_t start, length; "
                    "bool is_signed, big_endian; };");
  } else {
    append(lines, {"// CAN FD frames up to 64 bytes: start bits up to 511.",
                   "struct SignalInfo { const char* name; const char* unit; double factor, offset, min, max; std::uint16_t start; "
                   "std::uint8_t length; bool is_signed, big_endian; };"});
  }
  append(lines, {"", kDetail});
  for (std::size_t i = 0; i < db.messages.size(); ++i) append(lines, message_lines(db.messages[i], names[i]));
  std::vector<const Message*> received, sent;
  std::vector<std::string> received_types, sent_types;
  if (request.node != dbc::kNoNode) {  // else a header for the whole bus (a logger's): no node of its own
    for (std::size_t i = 0; i < db.messages.size(); ++i) {
      const Message& m = db.messages[i];
      if (std::any_of(m.signals.begin(), m.signals.end(), [&](const Signal& s) {
            return std::find(s.receivers.begin(), s.receivers.end(), request.node) != s.receivers.end();
          })) {
        received.push_back(&m);
        received_types.push_back(names[i].type);
      }
      if (m.sender == request.node || std::find(m.transmitters.begin(), m.transmitters.end(), request.node) != m.transmitters.end()) {
        sent.push_back(&m);
        sent_types.push_back(names[i].type);
      }
    }
  }
  if (auto it = db.node_comments.find(request.node); it != db.node_comments.end())
    append(lines, comment_lines(request.node + ": " + it->second, ""));
  append(lines, comment_lines("The frames " + request.node + " receives (one of their signals names it as a receiver) and sends (it is the sender, "
                                  "or in BO_TX_BU_): ids without the extended flag, as each struct's kId.",
                              ""));
  append(lines, id_array_lines("kReceivedIds", received.data(), received.size(), received_types));
  append(lines, id_array_lines("kTransmittedIds", sent.data(), sent.size(), sent_types));
  append(lines, {"", "}  // namespace " + request.ns, ""});
  return join(lines, "\n");
}

}  // namespace lptn::codegen
