// The page: the template with its styles and scripts inlined, so that the file opens offline.
#include <string>
#include <string_view>

#include "tools/report/embedded_assets.hpp"
#include "tools/report/report.hpp"

namespace lptn::report {
namespace {

void replace(std::string& page, std::string_view placeholder, std::string_view with) {
  const auto at = page.find(placeholder);
  if (at == std::string::npos) throw std::logic_error("report template lacks " + std::string(placeholder));
  page.replace(at, placeholder.size(), with);
}

// A browser would try to fetch the source map named on the minified file's last line.
std::string without_source_map(std::string_view js) {
  const auto at = js.rfind("//# sourceMappingURL=");
  return std::string(at == std::string_view::npos ? js : js.substr(0, at));
}

// JSON inside <script>: only "</" could end the element early; "<\/" is the same JSON string.
std::string script_safe(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    out += text[i];
    if (text[i] == '<' && i + 1 < text.size() && text[i + 1] == '/') out += '\\';
  }
  return out;
}

}  // namespace

std::string render_html(const nlohmann::json& data) {
  std::string page(assets::report_html);
  replace(page, "/*@DYGRAPH_CSS@*/", assets::dygraph_css);
  replace(page, "/*@REPORT_CSS@*/", assets::report_css);
  replace(page, "/*@DYGRAPH_JS@*/", without_source_map(assets::dygraph_js));
  replace(page, "/*@SYNCHRONIZER_JS@*/", assets::synchronizer_js);
  replace(page, "/*@REPORT_JS@*/", assets::report_js);
  replace(page, "@REPORT_DATA@", script_safe(data.dump()));
  return page;
}

}  // namespace lptn::report
