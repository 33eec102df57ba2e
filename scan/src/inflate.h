#pragma once

#include <cstdint>
#include <string>

#include "wearscar/scan/read_scan.h"

namespace wearscar::scan::internal {

// Decompression limits of one file (ReadScanOptions), with the running
// total of what its members have expanded to.
class InflateBudget {
 public:
  explicit InflateBudget(const ReadScanOptions& options) : o_(options) {}
  // Before inflating `compressed` bytes to a stated `expanded` (or, while
  // inflating, to what has come out so far): throws ScanError naming
  // `where` when the member, the ratio beyond the free allowance, or the
  // file's total would pass its limit. `cap` lowers the member limit (small
  // XML members). Returns nothing; Spend adds to the total.
  void Check(std::uint64_t compressed,
             std::uint64_t expanded,
             std::uint64_t cap,
             const std::string& where) const;
  void Spend(std::uint64_t expanded) { total_ += expanded; }

 private:
  const ReadScanOptions& o_;
  std::uint64_t total_ = 0;
};

// A zstd frame decompressed within the budget: the size stated in the
// frame is checked before any allocation; a frame that states none is
// inflated in steps, checked as it grows. Throws ScanError naming `where`.
std::string ZstdDecompress(const std::string& frame,
                           InflateBudget* budget,
                           std::uint64_t cap,
                           const std::string& where);

}  // namespace wearscar::scan::internal
