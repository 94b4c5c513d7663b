// SHA-256 of bytes and of files, lower-case hex: calibration files record the hash of every data
// file they were fitted to (and TD3's agent file), so that a result can be traced to the exact
// bytes; lptn check compares them.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace lptn::hostio {

std::string sha256_hex(const void* data, std::size_t size);
// Throws std::runtime_error "FILE: cannot read (missing or not readable)" or "FILE: read failed".
std::string sha256_file(const std::filesystem::path& path);
// Every file's, in order, the files over `threads` threads (a fleet dump's hundreds of MB are
// seconds of one core); a file that cannot be read throws as sha256_file does, the first in order.
std::vector<std::string> sha256_files(const std::vector<std::filesystem::path>& paths, int threads);

}  // namespace lptn::hostio
