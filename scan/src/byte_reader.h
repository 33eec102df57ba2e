#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>

#include "wearscar/scan/height_map.h"
#include "wearscar/support/text.h"

namespace wearscar::scan::internal {

// Bounds-checked little-endian reads; errors name the file and byte offset.
class ByteReader {
 public:
  ByteReader(const std::string& bytes, std::string name)
      : bytes_(bytes), name_(std::move(name)) {}

  template <typename T>
  T At(std::uint64_t offset, const char* what) const {
    Need(offset, sizeof(T), what);
    T v;
    std::memcpy(&v, bytes_.data() + offset, sizeof(T));
    return v;
  }
  // The same, stored most significant byte first (Zygo MetroPro).
  template <typename T>
  T AtBigEndian(std::uint64_t offset, const char* what) const {
    Need(offset, sizeof(T), what);
    unsigned char b[sizeof(T)];
    std::memcpy(b, bytes_.data() + offset, sizeof(T));
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) {
      std::swap(b[i], b[sizeof(T) - 1 - i]);
    }
    T v;
    std::memcpy(&v, b, sizeof(T));
    return v;
  }
  // A fixed-width text field: up to its first NUL, without surrounding
  // spaces.
  std::string Text(std::uint64_t offset,
                   std::uint64_t size,
                   const char* what) const {
    Need(offset, size, what);
    std::string_view s(bytes_.data() + offset, size);
    s = s.substr(0, s.find('\0'));
    const auto first = s.find_first_not_of(" \t\r\n");
    if (first == std::string_view::npos) return {};
    const auto last = s.find_last_not_of(" \t\r\n");
    return std::string(s.substr(first, last - first + 1));
  }
  void Need(std::uint64_t offset, std::uint64_t size, const char* what) const {
    if (offset > bytes_.size() || size > bytes_.size() - offset) {
      throw ScanError(fmt::format(
          "{}: byte {}: truncated: {} needs {} bytes, the file has {} "
          "bytes",
          name_,
          offset,
          what,
          size,
          bytes_.size()));
    }
  }
  const char* Data(std::uint64_t offset) const {
    return bytes_.data() + offset;
  }
  std::uint64_t size() const { return bytes_.size(); }
  const std::string& name() const { return name_; }

 private:
  const std::string& bytes_;
  std::string name_;
};

// Up to `max` bytes of a header or cell for an error message.
using support::Printable;

// Refuses a map of `cols` x `rows` read at byte `offset` unless both are
// positive and the map has at most kMaxPixels points: checked before any
// allocation.
inline void CheckMapSize(const ByteReader& in,
                         std::uint64_t offset,
                         std::int64_t cols,
                         std::int64_t rows) {
  if (cols <= 0 || rows <= 0 || cols > kMaxPixels || rows > kMaxPixels ||
      cols * rows > kMaxPixels) {
    throw ScanError(fmt::format(
        "{}: byte {}: a map of {} x {} points; expected 1 to {} points",
        in.name(),
        offset,
        cols,
        rows,
        kMaxPixels));
  }
}

}  // namespace wearscar::scan::internal
