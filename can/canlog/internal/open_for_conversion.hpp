// A log opened for lptn convert (log -> CSV, log -> log): one that cannot be opened is the
// conversion's error, which the command line reports as bad input.
#pragma once

#include <filesystem>

#include "can/canfile/can_log.hpp"
#include "can/canlog/convert.hpp"

namespace lptn::canlog::internal {

inline canfile::OpenedLog open_for_conversion(const std::filesystem::path& log, const canfile::LogSelection& select) {
  try {
    return canfile::open_log(log, select);
  } catch (const canfile::LogError& e) {
    throw ConvertError(e.what());
  }
}

}  // namespace lptn::canlog::internal
