#include "simulator/plant/cycle_kind.hpp"

namespace lptn::plant {

std::string_view to_string(CycleKind kind) {
  switch (kind) {
    case CycleKind::suburban: return "suburban";
    case CycleKind::regional: return "regional";
    case CycleKind::intercity: return "intercity";
    case CycleKind::hilly: return "hilly";
    case CycleKind::shunting: return "shunting";
  }
  return "unknown";
}

std::optional<CycleKind> cycle_kind_from_string(std::string_view name) {
  for (const CycleKind kind : kAllCycleKinds) {
    if (to_string(kind) == name) return kind;
  }
  return std::nullopt;
}

}  // namespace lptn::plant
