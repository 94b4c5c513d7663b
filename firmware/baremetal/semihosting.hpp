// ARM semihosting on the Cortex-M (`bkpt 0xAB`, operation in r0, argument block in r1): the debugger,
// or qemu with -semihosting-config, does the file I/O for the bare-metal replay image. Only what
// the image needs; no heap.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace lptn::semihosting {

enum Op : int { kOpen = 0x01, kClose = 0x02, kWrite = 0x05, kRead = 0x06, kGetCmdline = 0x15, kExitExtended = 0x20 };

inline int call(int op, const void* arg) {
  register int r0 asm("r0") = op;
  register const void* r1 asm("r1") = arg;
  asm volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

inline std::uint32_t word(const void* p) { return static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(p)); }

// mode: 0 "r", 1 "rb", 4 "w", 5 "wb". A handle, or -1.
inline int open(const char* path, int mode) {
  const std::uint32_t args[3] = {word(path), static_cast<std::uint32_t>(mode), static_cast<std::uint32_t>(std::strlen(path))};
  return call(kOpen, args);
}

inline void close(int handle) {
  const std::uint32_t args[1] = {static_cast<std::uint32_t>(handle)};
  call(kClose, args);
}

// Bytes read (0 at the end).
inline std::size_t read(int handle, char* buf, std::size_t n) {
  const std::uint32_t args[3] = {static_cast<std::uint32_t>(handle), word(buf), static_cast<std::uint32_t>(n)};
  const int not_read = call(kRead, args);
  return not_read < 0 ? 0 : n - static_cast<std::size_t>(not_read);
}

// true if every byte was written.
inline bool write(int handle, const char* s, std::size_t n) {
  const std::uint32_t args[3] = {static_cast<std::uint32_t>(handle), word(s), static_cast<std::uint32_t>(n)};
  return call(kWrite, args) == 0;
}

// The command line qemu was given (-semihosting-config ...,arg=A,arg=B): "A B".
inline bool command_line(char* buf, std::size_t size) {
  std::uint32_t args[2] = {word(buf), static_cast<std::uint32_t>(size)};
  return call(kGetCmdline, args) == 0;
}

[[noreturn]] inline void exit(int code) {
  const std::uint32_t args[2] = {0x20026u, static_cast<std::uint32_t>(code)};  // ADP_Stopped_ApplicationExit
  call(kExitExtended, args);
  for (;;) {
  }
}

}  // namespace lptn::semihosting
