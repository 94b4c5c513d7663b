// Files inlined into every report, embedded into the program at build time (embed.cmake): the
// page's template, script and styles, and Debian's dygraphs.
#pragma once

#include <string_view>

namespace lptn::report::assets {

extern const std::string_view report_html;
extern const std::string_view report_js;
extern const std::string_view report_css;
extern const std::string_view dygraph_js;
extern const std::string_view dygraph_css;
extern const std::string_view synchronizer_js;

}  // namespace lptn::report::assets
