// How a finding names the cycles it concerns: "a .. b" for a run of them, the name for one.
#pragma once

#include <string>
#include <vector>

namespace lptn::diagnose::internal {

inline std::string cycle_span(const std::vector<std::string>& cycles) {
  if (cycles.empty()) return "";
  return cycles.size() == 1 ? cycles.front() : cycles.front() + " .. " + cycles.back();
}

}  // namespace lptn::diagnose::internal
