// Fuzz target: an MDF4 bus logging file (can/canfile/mdf4_read.cpp), as `lptn replay` and `lptn
// convert` read it. Input: the file's bytes.
//
// Reading must end, whatever the bytes (links that loop, lists of absurd length, zipped blocks
// that claim gigabytes); every frame it gives must be one the bus could carry, on a named channel;
// every damaged block or record must come with its reason, which names a byte offset.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>

#include "fuzz_check.hpp"
#include "can/canfile/can_log.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  std::FILE* stream = fmemopen(const_cast<std::uint8_t*>(data), size, "rb");
  if (!stream) return 0;
  std::unique_ptr<lptn::frames::FrameSource> source;
  try {
    source = lptn::canfile::open_log(stream, lptn::canfile::LogFormat::mdf4, "fuzz");
  } catch (const lptn::canfile::LogError&) {
    return 0;  // no identification or header block: refused as a whole
  }
  lptn::fw::TimeUs t = 0;
  lptn::fw::CanFrame f;
  const char* why = nullptr;
  std::size_t last_record = 0;
  for (lptn::frames::FrameSource::Status s; (s = source->next(t, f, why)) != lptn::frames::FrameSource::Status::end;) {
    LPTN_FUZZ_CHECK(source->record() > last_record, "record numbers do not count up");
    last_record = source->record();
    if (s == lptn::frames::FrameSource::Status::bad) {
      LPTN_FUZZ_CHECK(why != nullptr && std::strncmp(why, "byte ", 5) == 0, "a bad record without its block's offset");
      continue;
    }
    LPTN_FUZZ_CHECK(f.len <= (f.fd ? 64 : 8), "data length beyond the frame kind's");
    LPTN_FUZZ_CHECK(f.id <= 0x1FFFFFFFu, "id beyond 29 bits");
    LPTN_FUZZ_CHECK(f.error || f.extended || f.id <= 0x7FFu, "standard id beyond 11 bits");
    LPTN_FUZZ_CHECK(t >= 0, "a time before 1970");
    LPTN_FUZZ_CHECK(!source->channel().empty(), "a frame without its channel");
  }
  return 0;
}
