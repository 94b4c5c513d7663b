#pragma once
// The kinds of service a driving cycle imitates, and their names on the command line / in files.

#include <optional>
#include <string_view>

namespace lptn::plant {

enum class CycleKind { suburban, regional, intercity, hilly, shunting };

inline constexpr CycleKind kAllCycleKinds[] = {CycleKind::suburban, CycleKind::regional,
                                               CycleKind::intercity, CycleKind::hilly,
                                               CycleKind::shunting};

std::string_view to_string(CycleKind kind);

// Exact, lower-case names as printed by to_string; nullopt for anything else.
std::optional<CycleKind> cycle_kind_from_string(std::string_view name);

}  // namespace lptn::plant
