#include "can/canfile/internal/inflate.hpp"

#include <libdeflate.h>

#include <new>

namespace lptn::canfile {

Inflater::Inflater() : decompressor_(libdeflate_alloc_decompressor()) {
  if (decompressor_ == nullptr) throw std::bad_alloc();
}

Inflater::~Inflater() { libdeflate_free_decompressor(decompressor_); }

bool Inflater::inflate_exactly(const std::uint8_t* in, std::size_t in_size, std::uint8_t* out, std::size_t out_size) {
  // No actual size asked for: libdeflate then wants exactly out_size bytes (LIBDEFLATE_SHORT_OUTPUT
  // for fewer, LIBDEFLATE_INSUFFICIENT_SPACE for more).
  return libdeflate_zlib_decompress(decompressor_, in, in_size, out, out_size, nullptr) == LIBDEFLATE_SUCCESS;
}

}  // namespace lptn::canfile
