// A CAN_RAW socket on a named interface: kernel filters for the ids the estimator reads, error
// frames delivered, receive-buffer overruns counted (SO_RXQ_OVFL), frames written back.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "lptn/firmware/can_frame.hpp"

namespace lptn::fw {

class CanSocket {
 public:
  CanSocket() = default;
  CanSocket(const CanSocket&) = delete;
  CanSocket& operator=(const CanSocket&) = delete;
  ~CanSocket();

  // Opens and binds; only `ids` (SocketCAN ids: extended ones with CAN_EFF_FLAG) and error frames
  // pass the kernel's filter. On failure returns false with a one-line reason in `error`.
  bool open(const std::string& interface, const std::uint32_t* ids, std::size_t count, std::string& error);
  int fd() const { return fd_; }

  enum class Read { frame, none, failed };
  // Non-blocking. `overrun` is set when the kernel dropped frames since the previous read.
  Read read(CanFrame& frame, bool& overrun);
  bool write(const CanFrame& frame);
  // The socket's pending error (SO_ERROR), cleared by reading it; 0: none. poll() reports POLLERR
  // for as long as one is pending (ENODEV once the interface is removed), so a loop that waits on
  // the socket must take it or spin.
  int take_error();

 private:
  int fd_ = -1;
  std::uint32_t dropped_ = 0;
};

}  // namespace lptn::fw
