// Reading a rendered report page in a test: Debian's chromium headless, the JSON the generator
// embedded, and the attributes the page's script sets on what it drew.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "lptn_testing/temp_dir.hpp"

namespace lptn::testing {

// chromium headless as root; a fresh profile, nothing fetched in the background.
inline std::string chromium(const std::filesystem::path& profile) {
  return "/usr/bin/chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
         "--disable-background-networking --disable-component-update --disable-sync --user-data-dir=" +
         profile.string() + " ";
}

inline int shell(const std::string& cmd) { return std::system(cmd.c_str()); }

// The JSON the generator embedded in the page (its "<\/" is JSON's own escape of '/').
inline nlohmann::json page_data(const std::string& html) {
  const std::string open = "<script id=\"report-data\" type=\"application/json\">";
  const std::size_t from = html.find(open);
  if (from == std::string::npos) return nullptr;
  const std::size_t a = from + open.size();
  return nlohmann::json::parse(html.substr(a, html.find("</script>", a) - a));
}

// The value of attribute `name` in the first tag of `chunk` that has it; "" if none.
inline std::string attribute(const std::string& chunk, const std::string& name) {
  std::smatch m;
  return std::regex_search(chunk, m, std::regex(" " + name + "=\"([^\"]*)\"")) ? m[1].str() : "";
}

// The markup from the element with attr="value" (e.g. data-cycle="x") up to the next element
// with that attribute: the element and what follows it, enough for the attributes inside.
inline std::string element_chunk(const std::string& dom, const std::string& attr, const std::string& value) {
  const std::size_t at = dom.find(attr + "=\"" + value + "\"");
  if (at == std::string::npos) return "";
  const std::size_t next = dom.find(attr + "=\"", at + 1);
  return dom.substr(at, next == std::string::npos ? std::string::npos : next - at);
}

// Every value of `name` in `chunk`, in order.
inline std::vector<std::string> attributes(const std::string& chunk, const std::string& name) {
  std::vector<std::string> out;
  const std::regex re(" " + name + "=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(chunk.begin(), chunk.end(), re); it != std::sregex_iterator(); ++it)
    out.push_back((*it)[1].str());
  return out;
}

// The page as chromium leaves it after its scripts ran (a fresh profile each time); "" when chromium
// fails, with its messages in `log`.
inline std::string dump_dom(const std::filesystem::path& page, const std::filesystem::path& log) {
  TempDir profile;
  const std::filesystem::path dom = profile.path() / "dom.html";
  if (shell(chromium(profile.path() / "profile") + "--virtual-time-budget=10000 --dump-dom file://" + page.string() +
            " >" + dom.string() + " 2>" + log.string()) != 0)
    return "";
  return slurp(dom);
}

// What the page's error box says: JavaScript errors, ours or dygraphs'.
inline std::string page_errors(const std::string& dom) {
  std::smatch m;
  static const std::regex errors(R"(<div id="errors"[^>]*>([\s\S]*?)</div>\s*<header)");
  return std::regex_search(dom, m, errors) ? m[1].str() : "no error box: not the report's page";
}

}  // namespace lptn::testing
