#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <string>

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

}  // namespace wearscar::scan::internal
