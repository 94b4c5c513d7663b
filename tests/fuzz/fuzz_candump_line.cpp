// Fuzz target: one line of a candump log (lptn/firmware/candump_line.hpp), as the daemon and
// `lptn replay` read them. Input: the line's bytes.
//
// Parsing must reject or accept without reading past the line; what it accepts must be a frame
// the bus could carry, and format_candump_line must write it back as a line that parses to the
// same frame and time.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <vector>

#include "lptn/firmware/candump_line.hpp"
#include "fuzz_check.hpp"

namespace {

using lptn::fw::CandumpRecord;
using lptn::fw::CanFrame;

void check_plausible(const CanFrame& f) {
  LPTN_FUZZ_CHECK(f.len <= (f.fd ? 64 : 8), "data length beyond the frame kind's");
  LPTN_FUZZ_CHECK(f.extended ? f.id <= 0x1FFFFFFFu : f.id <= 0x7FFu, "id beyond its width");
  LPTN_FUZZ_CHECK(!f.error || f.extended, "an error frame has the extended id form");
  LPTN_FUZZ_CHECK(!(f.remote && f.fd), "CAN FD has no remote frames");
}

void check_same(const CandumpRecord& a, const CandumpRecord& b) {
  LPTN_FUZZ_CHECK(a.time_us == b.time_us, "time");
  const CanFrame &f = a.frame, &g = b.frame;
  LPTN_FUZZ_CHECK(f.id == g.id, "id");
  LPTN_FUZZ_CHECK(f.len == g.len, "length");
  LPTN_FUZZ_CHECK(f.extended == g.extended && f.remote == g.remote && f.error == g.error && f.fd == g.fd, "flags");
  LPTN_FUZZ_CHECK(std::memcmp(f.data, g.data, sizeof f.data) == 0, "data");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view line(reinterpret_cast<const char*>(data), size);
  CandumpRecord first;
  if (const char* error = lptn::fw::parse_candump_line(line, first)) {
    LPTN_FUZZ_CHECK(std::strlen(error) > 0, "an error without a reason");
    return 0;
  }
  check_plausible(first.frame);
  LPTN_FUZZ_CHECK(!first.interface.empty(), "empty interface name");
  // The interface is a view into the line.
  LPTN_FUZZ_CHECK(first.interface.data() >= line.data() &&
                      first.interface.data() + first.interface.size() <= line.data() + line.size(),
                  "interface name outside the line");

  // The documented 200 bytes suffice for any frame with an interface name of a usual length;
  // a fuzzed name may be as long as the line.
  std::vector<char> buf(200 + first.interface.size());
  const std::size_t n = lptn::fw::format_candump_line(buf.data(), buf.size(), first.time_us, first.interface, first.frame);
  LPTN_FUZZ_CHECK(n > 0 && n < buf.size(), "format_candump_line found its buffer too small");

  CandumpRecord second;
  const char* error = lptn::fw::parse_candump_line(std::string_view(buf.data(), n), second);
  LPTN_FUZZ_CHECK(error == nullptr, error);
  check_same(first, second);
  LPTN_FUZZ_CHECK(second.interface == first.interface, "interface name");
  return 0;
}
