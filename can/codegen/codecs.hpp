// The codecs header of a DBC: one struct per frame with its signals' raw values, pack() and
// unpack(), each signal's scaling, range and value names, and the ids a node receives and sends.
#pragma once

#include <string>
#include <vector>

#include "can/dbc/dbc.hpp"

namespace lptn::codegen {

struct CodecsRequest {
  std::string node;       // whose received and sent ids to list; dbc::kNoNode: none (the whole bus)
  std::string ns;         // C++ namespace
  std::string dbc_name;   // the DBC's file name, for the first line
};

// The header's text, from the Database read for `request.node`. Throws dbc::Error; the C++ names'
// renames are added to `warnings`.
std::string codecs_header(const dbc::Database& db, const CodecsRequest& request, std::vector<dbc::Warning>& warnings);

}  // namespace lptn::codegen
