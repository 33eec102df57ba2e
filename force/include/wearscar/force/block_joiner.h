#pragma once
// A test the tribometer's software writes as a file per block (`wearscar
// watch DIR --pattern GLOB`, wearscar.watch(DIR, pattern=GLOB)): the files
// of DIR matching GLOB, in their names' natural order (run_2 before
// run_10), joined into one file as they grow, which a ForceFollower
// follows as it follows one export. A block is
// finished once a later one exists. The joining is the blocks one after
// the other, each with its header: an export of repeated blocks (as a
// CETR UMT's steps), whose clock may continue or start again in each,
// which the reader joins.

#include <cstdint>
#include <string>
#include <vector>

namespace wearscar::force {

// Whether `a` comes before `b` in natural order: runs of digits compared as
// numbers ("run_2" < "run_10"), the rest byte by byte.
bool NaturalLess(const std::string& a, const std::string& b);

class BlockJoiner {
 public:
  // Refuses (ForceError) a `folder` that is not one or an empty pattern;
  // empties `joined`.
  BlockJoiner(std::string folder, std::string pattern, std::string joined);

  // Appends to the joined file what the blocks hold beyond what was taken.
  // Returns a line for the user when a block was finished or started (""
  // otherwise).
  std::string Update();

  const std::string& joined() const { return joined_; }
  // The blocks taken (finished, and the one being followed).
  const std::vector<std::string>& blocks() const { return taken_; }

 private:
  std::vector<std::string> Blocks() const;
  // Appends the current block's bytes from offset_: its complete lines, or
  // all of it when `finished` (a last line given its line break). True
  // when a finished block has been taken to its end.
  bool Append(bool finished);

  std::string folder_, pattern_, joined_;
  std::vector<std::string> taken_;
  std::uintmax_t offset_ = 0;
};

}  // namespace wearscar::force
