// Little helpers for the checkpoint's binary image: append / read plain values and arrays, with
// bounds checks on reading (a truncated image throws instead of reading past its end).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace lptn::td3::internal {

class ByteWriter {
 public:
  template <class T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    put_bytes(&value, sizeof(T));
  }
  template <class T>
  void put_array(const T* data, std::size_t count) {
    static_assert(std::is_trivially_copyable_v<T>);
    put<std::uint64_t>(count);
    if (count > 0) put_bytes(data, count * sizeof(T));
  }
  void put_string(const std::string& s) { put_array(s.data(), s.size()); }
  void put_bytes(const void* data, std::size_t bytes) {
    data_.append(static_cast<const char*>(data), bytes);
  }
  std::string& data() { return data_; }

 private:
  std::string data_;
};

// Thrown on a short or inconsistent image; the agent turns it into a message naming the file.
struct FormatError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class ByteReader {
 public:
  ByteReader(const char* data, std::size_t size) : data_(data), size_(size) {}
  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    get_bytes(&value, sizeof(T));
    return value;
  }
  // Reads an array written by put_array, which must hold exactly `count` elements.
  template <class T>
  void get_array(T* data, std::size_t count, const char* what) {
    const auto stored = get<std::uint64_t>();
    if (stored != count) throw FormatError(std::string(what) + ": wrong size");
    if (count > 0) get_bytes(data, count * sizeof(T));
  }
  std::string get_string(std::size_t max_size, const char* what) {
    const auto n = get<std::uint64_t>();
    if (n > max_size || n > remaining()) throw FormatError(std::string(what) + ": bad length");
    std::string s(data_ + pos_, static_cast<std::size_t>(n));
    pos_ += static_cast<std::size_t>(n);
    return s;
  }
  void get_bytes(void* out, std::size_t bytes) {
    if (bytes > remaining()) throw FormatError("truncated");
    std::memcpy(out, data_ + pos_, bytes);
    pos_ += bytes;
  }
  std::size_t remaining() const { return size_ - pos_; }

 private:
  const char* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

// 64-bit FNV-1a over 8-byte words (then the tail bytes): cheap enough for a buffer of tens of MB.
inline std::uint64_t checksum(const char* data, std::size_t size) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  constexpr std::uint64_t kPrime = 0x100000001b3ULL;
  std::size_t i = 0;
  for (; i + 8 <= size; i += 8) {
    std::uint64_t w;
    std::memcpy(&w, data + i, 8);
    h = (h ^ w) * kPrime;
    h ^= h >> 29;
  }
  for (; i < size; ++i) h = (h ^ static_cast<unsigned char>(data[i])) * kPrime;
  return h;
}

}  // namespace lptn::td3::internal
