#include "can/codegen/cxx_names.hpp"

#include <algorithm>
#include <functional>
#include <map>
#include <optional>
#include <regex>
#include <set>

namespace lptn::codegen {
namespace {

const std::set<std::string> kKeywords = {
    "alignas", "alignof", "and", "and_eq", "asm", "auto", "bitand", "bitor", "bool", "break", "case", "catch", "char",
    "char8_t", "char16_t", "char32_t", "class", "compl", "concept", "const", "consteval", "constexpr", "constinit",
    "const_cast", "continue", "co_await", "co_return", "co_yield", "decltype", "default", "delete", "do", "double",
    "dynamic_cast", "else", "enum", "explicit", "export", "extern", "false", "float", "for", "friend", "goto", "if",
    "inline", "int", "long", "mutable", "namespace", "new", "noexcept", "not", "not_eq", "nullptr", "operator", "or",
    "or_eq", "private", "protected", "public", "register", "reinterpret_cast", "requires", "return", "short", "signed",
    "sizeof", "static", "static_assert", "static_cast", "struct", "switch", "template", "this", "thread_local", "throw",
    "true", "try", "typedef", "typeid", "typename", "union", "unsigned", "using", "virtual", "void", "volatile",
    "wchar_t", "while", "xor", "xor_eq"};
// pack() and unpack() use these as parameters and locals; a member of the same name would be shadowed.
const std::set<std::string> kPackLocals = {"dst", "src", "size", "bits", "i"};
const char* const kStructConstants[] = {"kId",         "kExtended", "kLength", "kCycleTimeMs", "kName",     "kSender",
                                        "kSignals",    "kNumSignals", "pack",  "unpack",       "SignalInfo"};
const char* const kNamespaceNames[] = {"SignalInfo", "detail", "kReceivedIds", "kTransmittedIds"};
const std::string kDefined = "a name the header defines";

using Owners = std::map<std::string, std::string>;  // C++ name -> what took it

bool valid(const std::string& name) {
  static const std::regex pattern("[A-Za-z][A-Za-z0-9_]*");
  return std::regex_match(name, pattern);
}
bool is_upper(char c) { return c >= 'A' && c <= 'Z'; }
bool is_lower(char c) { return c >= 'a' && c <= 'z'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }
char upper(char c) { return is_lower(c) ? static_cast<char>(c - 'a' + 'A') : c; }
char lower(char c) { return is_upper(c) ? static_cast<char>(c - 'A' + 'a') : c; }

class Namer {
 public:
  Namer(const std::string& path, std::vector<dbc::Warning>& warnings) : path_(path), warnings_(warnings) {}

  [[noreturn]] void fail(int line, const std::string& reason) const {
    throw dbc::Error(path_ + ":" + std::to_string(line) + ": " + reason);
  }
  void claim(Owners& names, const std::string& name, const std::string& owner, int line) const {
    if (!valid(name)) fail(line, owner + " gives no valid C++ name ('" + name + "')");
    if (auto it = names.find(name); it != names.end()) fail(line, owner + ": its C++ name '" + name + "' clashes with " + it->second);
    names[name] = owner;
  }
  // The first candidate whose derived names are all free; a warning says when it is not the first.
  std::string claim_free(Owners& names, const std::vector<std::string>& candidates,
                         const std::function<std::vector<std::string>(const std::string&)>& derived, const std::string& owner,
                         int line) const {
    std::optional<std::pair<std::string, std::string>> first;
    for (const std::string& candidate : candidates) {
      const std::vector<std::string> wanted = derived(candidate);
      if (!valid(wanted[0])) fail(line, owner + " gives no valid C++ name ('" + wanted[0] + "')");
      const auto taken = std::find_if(wanted.begin(), wanted.end(), [&](const std::string& n) { return names.count(n) > 0; });
      if (taken == wanted.end()) {
        if (first)
          warnings_.push_back({line, owner + ": its C++ name '" + first->first + "' clashes with " + first->second + "; named '" +
                                         wanted[0] + "' instead"});
        for (const std::string& n : wanted) names[n] = owner;
        return candidate;
      }
      if (!first) first = std::pair{*taken, names.at(*taken)};
    }
    fail(line, owner + ": its C++ name '" + first->first + "' clashes with " + first->second);
  }

 private:
  const std::string& path_;
  std::vector<dbc::Warning>& warnings_;
};

std::vector<std::string> numbered(const std::string& base, const std::vector<std::string>& first_suffixes = {}) {
  std::vector<std::string> out{base};
  for (const std::string& s : first_suffixes) out.push_back(base + s);
  for (int n = 2; n < 100; ++n) out.push_back(base + "_" + std::to_string(n));
  return out;
}
std::vector<std::string> itself(const std::string& name) { return {name}; }

std::string member_of(const std::string& base) {
  return kKeywords.count(base) || kPackLocals.count(base) ? base + "_" : base;
}

}  // namespace

std::string camel_case(const std::string& name) {
  std::string text;
  std::size_t pos = 0;
  while (pos <= name.size()) {
    std::size_t end = name.find('_', pos);
    if (end == std::string::npos) end = name.size();
    const std::string part = name.substr(pos, end - pos);
    pos = end + 1;
    if (part.empty()) continue;
    // Python's isupper(): a capital and no small letter. Such a word is Capitalised; others keep
    // their case but the first letter.
    const bool all_caps = std::any_of(part.begin(), part.end(), is_upper) && std::none_of(part.begin(), part.end(), is_lower);
    text += upper(part[0]);
    for (std::size_t i = 1; i < part.size(); ++i) text += all_caps ? lower(part[i]) : part[i];
  }
  return !text.empty() && is_digit(text[0]) ? "N" + text : text;
}

std::string snake_case(const std::string& name) {
  static const std::regex acronym("([A-Z]+)([A-Z][a-z])"), word("([a-z0-9])([A-Z])"), underscores("_+");
  std::string text = std::regex_replace(name, acronym, "$1_$2");
  text = std::regex_replace(text, word, "$1_$2");
  text = std::regex_replace(text, underscores, "_");
  const std::size_t first = text.find_first_not_of('_');
  text = first == std::string::npos ? "" : text.substr(first, text.find_last_not_of('_') - first + 1);
  std::transform(text.begin(), text.end(), text.begin(), lower);
  return !text.empty() && is_digit(text[0]) ? "n_" + text : text;
}

std::vector<std::string> enumerator_names(const std::vector<std::pair<std::int64_t, std::string>>& values) {
  const auto suffix = [](std::int64_t raw) {
    return raw >= 0 ? std::to_string(raw) : "minus_" + std::to_string(0 - static_cast<std::uint64_t>(raw));
  };
  std::vector<std::string> bases;
  for (const auto& [raw, description] : values) {
    // Runs of anything but ASCII letters and digits (bytes of UTF-8 included) become one '_'.
    std::string base;
    bool gap = false;
    for (const char c : description) {
      if (is_upper(c) || is_lower(c) || is_digit(c)) {
        if (gap) base += '_';
        gap = false;
        base += c;
      } else {
        gap = true;
      }
    }
    if (gap && !base.empty()) base += '_';
    const std::size_t first = base.find_first_not_of('_');
    base = first == std::string::npos ? "" : base.substr(first, base.find_last_not_of('_') - first + 1);
    if (base.empty())
      base = "value_" + suffix(raw);
    else if (is_digit(base[0]))
      base = "value_" + base;
    bases.push_back(kKeywords.count(base) ? base + "_" : base);
  }
  std::vector<std::string> names;
  for (std::size_t i = 0; i < bases.size(); ++i)
    names.push_back(std::count(bases.begin(), bases.end(), bases[i]) > 1 ? bases[i] + "_" + suffix(values[i].first) : bases[i]);
  return names;
}

std::vector<MessageNames> cxx_names(const dbc::Database& db, std::vector<dbc::Warning>& warnings) {
  Namer namer(db.path, warnings);
  Owners global;
  for (const char* n : kNamespaceNames) global[n] = kDefined;
  std::vector<MessageNames> out;
  for (const dbc::Message& m : db.messages) {
    MessageNames names;
    names.type = namer.claim_free(global, numbered(camel_case(m.name)), itself, "message " + m.name, m.line);
    Owners members;
    for (const char* n : kStructConstants) members[n] = kDefined;
    members[names.type] = "the struct's own name";
    for (const dbc::Signal& s : m.signals) {
      SignalNames sn;
      const bool multiplexed = s.mux == dbc::Signal::Mux::multiplexed;
      const auto derived = [&](const std::string& base) {
        std::vector<std::string> d{member_of(base), base + "_decode", base + "_encode", base + "_is_in_range"};
        if (multiplexed) d.push_back(base + "_is_present");
        return d;
      };
      sn.base = namer.claim_free(members, numbered(snake_case(s.name)), derived, "signal " + s.name, s.line);
      sn.member = member_of(sn.base);
      if (!s.values.empty()) {
        sn.enum_name = namer.claim_free(members, numbered(camel_case(s.name), {"Values"}), itself,
                                        "the values (VAL_) of " + s.name, s.line);
        sn.enumerators = enumerator_names(s.values);
        Owners enumerators;
        for (const std::string& n : sn.enumerators) namer.claim(enumerators, n, "VAL_ of " + s.name, s.line);
      }
      names.signals.push_back(std::move(sn));
    }
    out.push_back(std::move(names));
  }
  return out;
}

}  // namespace lptn::codegen
