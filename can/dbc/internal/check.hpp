// A parsed DBC document checked and resolved into the Database both routes use. Internal to can/dbc.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "can/dbc/dbc.hpp"
#include "can/dbc/internal/parser.hpp"

namespace lptn::dbc::internal {

// Frame bit (8 * byte + bit in byte) of each of the signal's value bits, least significant first:
// the checker's overlap and frame-size tests and the reader's decoding use this one layout.
std::vector<int> frame_bits(const Signal& s);

// Throws ParseError for what would make a frame undecodable; what it reads past goes into
// Database::warnings, in the order of their lines.
Database check(Document& doc, const std::string& path, std::string_view node);

}  // namespace lptn::dbc::internal
