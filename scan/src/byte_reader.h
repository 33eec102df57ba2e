#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "wearscar/scan/height_map.h"

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

// Up to `max` bytes of a header or cell for an error message, anything not
// printable ASCII written as \xNN and "..." after a cut.
inline std::string Printable(std::string_view text, std::size_t max = 40) {
  static const char kHex[] = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < text.size() && i < max; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  if (text.size() > max) out += "...";
  return out;
}

}  // namespace wearscar::scan::internal
