// A CAN frame from its id and bytes, for the log format suites' hand-made logs.
#pragma once

#include <cstdint>
#include <vector>

#include "lptn/firmware/can_frame.hpp"

namespace lptn::canfile {

inline fw::CanFrame make_frame(std::uint32_t id, bool extended, const std::vector<std::uint8_t>& data, bool fd = false) {
  fw::CanFrame f;
  f.id = id;
  f.extended = extended;
  f.fd = fd;
  f.len = static_cast<std::uint8_t>(data.size());
  for (std::size_t i = 0; i < data.size(); ++i) f.data[i] = data[i];
  return f;
}

}  // namespace lptn::canfile
