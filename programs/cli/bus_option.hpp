// --bus bus.toml, as replay, convert and vcan-bench read it: the map with its DBC, its warnings on
// stderr, a bad map one line of bad input.
#pragma once

#include <cstdio>
#include <memory>
#include <string>

#include "can/bus/bus_map.hpp"
#include "programs/cli/commands.hpp"

namespace lptn::cli {

inline std::unique_ptr<bus::BusMap> read_bus_map(const std::string& path) {
  try {
    auto map = bus::BusMap::read(path);
    for (const std::string& w : map->warnings()) std::fprintf(stderr, "%s\n", w.c_str());
    return map;
  } catch (const bus::MapError& e) {
    throw hostio::BadInput(e.what());
  }
}

}  // namespace lptn::cli
