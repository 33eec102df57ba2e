#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "inflate.h"

namespace wearscar::scan::internal {

// A read-only ZIP archive over bytes in memory (libzip), which it owns
// (libzip reads the buffer lazily). Errors are ScanError naming `name` and
// the member.
class ZipArchive {
 public:
  // The decompression limits of `options` apply to every member read.
  ZipArchive(std::string bytes,
             std::string name,
             const ReadScanOptions& options);
  ~ZipArchive();
  ZipArchive(const ZipArchive&) = delete;
  ZipArchive& operator=(const ZipArchive&) = delete;

  std::vector<std::string> Members() const;
  bool Has(const std::string& member) const;
  // Finds a member by exact name, or one whose path ends with "/" + name
  // (files nested in a top-level folder). Empty when absent.
  std::string Find(const std::string& name) const;
  // Reads a member within the limits (and at most `cap` bytes); the size
  // and ratio the archive states are checked before inflating.
  std::string Read(
      const std::string& member,
      std::uint64_t cap = std::numeric_limits<std::uint64_t>::max()) const;
  // The limits' running total, for members compressed once more (zstd).
  InflateBudget& budget() const { return budget_; }
  const std::string& name() const { return name_; }

 private:
  struct Impl;
  std::string bytes_;
  Impl* impl_;
  std::string name_;
  mutable InflateBudget budget_;
};

}  // namespace wearscar::scan::internal
