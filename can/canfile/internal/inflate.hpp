// A zlib stream (RFC 1950) of known inflated size, as BLF's log containers and MDF4's DZ blocks
// store their data, inflated into a buffer of that size. By libdeflate: inflating a whole buffer
// at once, it took half the time zlib's inflate did over the demo's BLF logs (39 against 74 ns a
// frame, parsing included), where inflation was most of a BLF replay's parsing.
#pragma once

#include <cstddef>
#include <cstdint>

struct libdeflate_decompressor;

namespace lptn::canfile {

class Inflater {
 public:
  Inflater();  // throws std::bad_alloc if the decompressor's tables cannot be allocated
  ~Inflater();
  Inflater(const Inflater&) = delete;
  Inflater& operator=(const Inflater&) = delete;

  // True if `in` starts with a zlib stream whose data is exactly `out_size` bytes and whose
  // Adler-32 check holds; the data is then in `out`. False for anything else (a corrupt stream,
  // more or fewer bytes), with `out` undefined. Bytes after the stream are not looked at.
  bool inflate_exactly(const std::uint8_t* in, std::size_t in_size, std::uint8_t* out, std::size_t out_size);

 private:
  libdeflate_decompressor* decompressor_;
};

}  // namespace lptn::canfile
