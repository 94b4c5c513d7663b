// Fuzz target: a whole CAN log file (can/canfile: candump, Vector ASC, Vector BLF), as `lptn
// replay` and `lptn convert` read them. Input: one byte choosing the format (its value modulo 3:
// candump, ASC, BLF), then the file's bytes.
//
// Reading must end, whatever the bytes; every frame it gives must be one the bus could carry, and
// every malformed record must come with its reason.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>

#include "fuzz_check.hpp"
#include "can/canfile/can_log.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using lptn::canfile::LogFormat;
  if (size < 1) return 0;
  const LogFormat format = static_cast<LogFormat>(data[0] % 3);
  // fmemopen refuses an empty buffer; a one-byte file of a space reads like an empty one.
  static const char kSpace[] = " ";
  void* bytes = size > 1 ? const_cast<std::uint8_t*>(data + 1) : static_cast<void*>(const_cast<char*>(kSpace));
  std::FILE* stream = fmemopen(bytes, size > 1 ? size - 1 : 1, "rb");
  if (!stream) return 0;
  std::unique_ptr<lptn::frames::FrameSource> source;
  try {
    source = lptn::canfile::open_log(stream, format, "fuzz");
  } catch (const lptn::canfile::LogError&) {
    return 0;  // not a BLF file header: refused as a whole
  }
  lptn::fw::TimeUs t = 0;
  lptn::fw::CanFrame f;
  const char* why = nullptr;
  std::size_t last_record = 0;
  for (lptn::frames::FrameSource::Status s; (s = source->next(t, f, why)) != lptn::frames::FrameSource::Status::end;) {
    LPTN_FUZZ_CHECK(source->record() >= last_record, "record numbers go back");
    last_record = source->record();
    if (s == lptn::frames::FrameSource::Status::bad) {
      LPTN_FUZZ_CHECK(why != nullptr && why[0] != '\0', "a bad record without its reason");
      continue;
    }
    LPTN_FUZZ_CHECK(f.len <= (f.fd ? 64 : 8), "data length beyond the frame kind's");
    LPTN_FUZZ_CHECK(f.id <= 0x1FFFFFFFu, "id beyond 29 bits");
    LPTN_FUZZ_CHECK(f.error || f.extended || f.id <= 0x7FFu, "standard id beyond 11 bits");
    LPTN_FUZZ_CHECK(t >= 0, "a time before 1970");
  }
  return 0;
}
