// The firmware's glue to a converter's bus: fw::BusDecoder for a bus map, decoding the map's frames
// through the codecs generated from the map's DBC (no DBC parsing on the target).
#pragma once

#include <string>

#include "can/bus/bus_map.hpp"

namespace lptn::codegen {

struct GlueRequest {
  std::string bus_name;         // the map's file name, for the first line
  std::string codecs;           // the include path of the DBC's generated codecs
  std::string codec_namespace;  // their namespace
  std::string ns;               // the glue's namespace
};

// Throws dbc::Error where the DBC's names cannot be C++ (the codecs' generation refuses it too).
std::string bus_glue_header(const bus::BusMap& map, const GlueRequest& request);

}  // namespace lptn::codegen
