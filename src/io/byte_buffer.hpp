// Minimal binary serialisation for checkpoints and binary trajectory files: append plain values to a
// byte vector and read them back, with truncation reported as a ConfigError naming the source.
//
// Values are stored in the host's native byte order. The engine only targets little-endian hosts
// (x86-64, AArch64 Linux), and the formats that use these helpers (checkpoint, GSD) are defined as
// little-endian, so the static_assert below turns a silent misread on a big-endian host into a
// build error instead of adding byte swapping that nothing would exercise.
#pragma once
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "mesodpd/config_error.hpp"

namespace mesodpd {

static_assert(std::endian::native == std::endian::little,
              "mesodpd binary formats assume a little-endian host (see io/byte_buffer.hpp)");

template <class T>
concept BytePod = std::is_trivially_copyable_v<T> && !std::is_pointer_v<T>;

// Appends values to a growing byte vector. Vectors and strings are written as a uint64 element
// count followed by the elements, so a reader knows how much to take without a schema.
class ByteWriter {
 public:
  template <BytePod T>
  void put(const T& value) {
    append_raw(&value, sizeof(T));
  }

  template <BytePod T, std::size_t Extent>
  void put_vector(std::span<T, Extent> values) {
    put<std::uint64_t>(values.size());
    append_raw(values.data(), values.size_bytes());
  }

  template <BytePod T>
  void put_vector(const std::vector<T>& values) {
    put_vector(std::span<const T>(values));
  }

  void put_string(std::string_view s) {
    put<std::uint64_t>(s.size());
    append_raw(s.data(), s.size());
  }

  // Raw bytes without a length prefix (the caller knows the size, e.g. a fixed-width field).
  void put_bytes(std::span<const std::byte> bytes) { append_raw(bytes.data(), bytes.size()); }

  [[nodiscard]] std::size_t size() const { return bytes_.size(); }
  [[nodiscard]] const std::vector<std::byte>& bytes() const { return bytes_; }
  [[nodiscard]] std::vector<std::byte> take() { return std::exchange(bytes_, {}); }

 private:
  // Kept out of line: when GCC 12 inlines the vector growth into every put() it reports false
  // -Wstringop-overflow warnings (it confuses the sizes of different inlined allocations).
  [[gnu::noinline]] void append_raw(const void* data, std::size_t n) {
    if (n == 0) return;  // data may be null for an empty span
    const std::size_t old_size = bytes_.size();
    bytes_.resize(old_size + n);
    std::memcpy(bytes_.data() + old_size, data, n);
  }

  std::vector<std::byte> bytes_;
};

// Reads what ByteWriter wrote. Every read checks the remaining length first; the context string
// (typically "checkpoint 'run.ckpt'") starts each error message so the user knows which file is bad.
class ByteReader {
 public:
  ByteReader(std::span<const std::byte> bytes, std::string context)
      : bytes_(bytes), context_(std::move(context)) {}

  template <BytePod T>
  T get() {
    T value;
    std::memcpy(&value, take(sizeof(T), "value").data(), sizeof(T));
    return value;
  }

  template <BytePod T>
  std::vector<T> get_vector() {
    const auto count = get<std::uint64_t>();
    // Check the length before allocating: a corrupted count must not become a huge allocation.
    if (count > remaining() / sizeof(T)) {
      throw ConfigError(context_ + ": truncated data: array of " + std::to_string(count) + " elements of " +
                        std::to_string(sizeof(T)) + " bytes at offset " + std::to_string(offset_) +
                        ", but only " + std::to_string(remaining()) + " bytes remain");
    }
    std::vector<T> values(static_cast<std::size_t>(count));
    const auto raw = take(values.size() * sizeof(T), "array");
    if (!raw.empty()) std::memcpy(values.data(), raw.data(), raw.size());
    return values;
  }

  std::string get_string() {
    const auto length = get<std::uint64_t>();
    if (length > remaining()) {
      throw ConfigError(context_ + ": truncated data: string of " + std::to_string(length) +
                        " bytes at offset " + std::to_string(offset_) + ", but only " +
                        std::to_string(remaining()) + " bytes remain");
    }
    const auto raw = take(static_cast<std::size_t>(length), "string");
    return std::string(reinterpret_cast<const char*>(raw.data()), raw.size());
  }

  // The next n bytes, without a length prefix.
  std::span<const std::byte> get_bytes(std::size_t n) { return take(n, "bytes"); }

  [[nodiscard]] std::size_t offset() const { return offset_; }
  [[nodiscard]] std::size_t remaining() const { return bytes_.size() - offset_; }
  [[nodiscard]] bool at_end() const { return offset_ == bytes_.size(); }
  [[nodiscard]] const std::string& context() const { return context_; }

  // Trailing bytes mean the reader and writer disagree about the layout: report it, do not ignore.
  void expect_end() const {
    if (!at_end()) {
      throw ConfigError(context_ + ": " + std::to_string(remaining()) +
                        " unexpected trailing bytes at offset " + std::to_string(offset_));
    }
  }

 private:
  std::span<const std::byte> take(std::size_t n, const char* what) {
    if (n > remaining()) {
      throw ConfigError(context_ + ": truncated data: reading a " + what + " of " + std::to_string(n) +
                        " bytes at offset " + std::to_string(offset_) + ", but only " +
                        std::to_string(remaining()) + " bytes remain");
    }
    auto out = bytes_.subspan(offset_, n);
    offset_ += n;
    return out;
  }

  std::span<const std::byte> bytes_;
  std::size_t offset_ = 0;
  std::string context_;
};

}  // namespace mesodpd
