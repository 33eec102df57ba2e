#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace wearscar::scan::internal {

// A read-only ZIP archive over bytes in memory (libzip), which it owns
// (libzip reads the buffer lazily). Errors are ScanError naming `name` and
// the member.
class ZipArchive {
 public:
  ZipArchive(std::string bytes, std::string name);
  ~ZipArchive();
  ZipArchive(const ZipArchive&) = delete;
  ZipArchive& operator=(const ZipArchive&) = delete;

  std::vector<std::string> Members() const;
  bool Has(const std::string& member) const;
  // Finds a member by exact name, or one whose path ends with "/" + name
  // (files nested in a top-level folder). Empty when absent.
  std::string Find(const std::string& name) const;
  // Reads a member; refuses members that decompress to more than max_bytes.
  std::string Read(const std::string& member, std::uint64_t max_bytes) const;

 private:
  struct Impl;
  std::string bytes_;
  Impl* impl_;
  std::string name_;
};

}  // namespace wearscar::scan::internal
