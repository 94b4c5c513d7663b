#include "socketcan.hpp"

#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace lptn::fw {

CanSocket::~CanSocket() {
  if (fd_ >= 0) ::close(fd_);
}

bool CanSocket::open(const std::string& interface, const std::uint32_t* ids, std::size_t count, std::string& error) {
  auto fail = [&](const char* what) {
    error = interface + ": " + what + ": " + std::strerror(errno);
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    return false;
  };
  fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (fd_ < 0) return fail("socket(PF_CAN, SOCK_RAW, CAN_RAW)");
  can_filter filters[16];
  if (count > 16) count = 16;
  for (std::size_t i = 0; i < count; ++i) {
    filters[i].can_id = ids[i];
    // Exactly this data frame: a standard id, or an extended one (CAN_EFF_FLAG set in ids[i]).
    filters[i].can_mask = ((ids[i] & CAN_EFF_FLAG) ? CAN_EFF_MASK : CAN_SFF_MASK) | CAN_EFF_FLAG | CAN_RTR_FLAG;
  }
  if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, filters, static_cast<socklen_t>(count * sizeof(can_filter))) < 0)
    return fail("CAN_RAW_FILTER");
  const can_err_mask_t errors = CAN_ERR_MASK;
  if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &errors, sizeof errors) < 0) return fail("CAN_RAW_ERR_FILTER");
  const int on = 1;
  if (::setsockopt(fd_, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on) < 0) return fail("SO_RXQ_OVFL");
  ifreq ifr{};
  if (interface.size() >= sizeof ifr.ifr_name) {
    errno = ENAMETOOLONG;
    return fail("interface name");
  }
  std::memcpy(ifr.ifr_name, interface.c_str(), interface.size() + 1);
  if (::ioctl(fd_, SIOCGIFINDEX, &ifr) < 0) return fail("no such CAN interface (SIOCGIFINDEX)");
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifr.ifr_ifindex;
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) < 0) return fail("bind");
  return true;
}

CanSocket::Read CanSocket::read(CanFrame& frame, bool& overrun) {
  can_frame raw{};
  iovec iov{&raw, sizeof raw};
  alignas(cmsghdr) char control[CMSG_SPACE(sizeof(std::uint32_t))];
  msghdr msg{};
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = control;
  msg.msg_controllen = sizeof control;
  const ssize_t n = ::recvmsg(fd_, &msg, 0);
  if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR ? Read::none : Read::failed;
  if (static_cast<std::size_t>(n) < sizeof raw) return Read::none;  // not a classic frame
  overrun = false;
  for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c; c = CMSG_NXTHDR(&msg, c)) {
    if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_RXQ_OVFL) {
      std::uint32_t dropped;
      std::memcpy(&dropped, CMSG_DATA(c), sizeof dropped);
      overrun = dropped != dropped_;
      dropped_ = dropped;
    }
  }
  frame = CanFrame{};
  frame.error = (raw.can_id & CAN_ERR_FLAG) != 0;
  frame.extended = (raw.can_id & CAN_EFF_FLAG) != 0;
  frame.remote = (raw.can_id & CAN_RTR_FLAG) != 0;
  frame.id = raw.can_id & (frame.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
  frame.len = raw.len > CAN_MAX_DLEN ? CAN_MAX_DLEN : raw.len;
  std::memcpy(frame.data, raw.data, frame.len);
  return Read::frame;
}

bool CanSocket::write(const CanFrame& frame) {
  can_frame raw{};
  raw.can_id = frame.id | (frame.extended ? CAN_EFF_FLAG : 0u);
  raw.len = frame.len > CAN_MAX_DLEN ? CAN_MAX_DLEN : frame.len;
  std::memcpy(raw.data, frame.data, raw.len);
  return ::write(fd_, &raw, sizeof raw) == static_cast<ssize_t>(sizeof raw);
}

int CanSocket::take_error() {
  int error = 0;
  socklen_t length = sizeof error;
  if (::getsockopt(fd_, SOL_SOCKET, SO_ERROR, &error, &length) != 0) return errno;
  return error;
}

}  // namespace lptn::fw
