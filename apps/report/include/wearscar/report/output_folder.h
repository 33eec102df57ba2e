#pragma once

// An output folder as wearscar writes it: every file atomically, a run's
// files staged and moved into place together, one writer at a time, and a
// manifest of what wearscar wrote so that a later run removes only its own
// stale files.

#include <stdexcept>
#include <string>
#include <vector>

namespace wearscar::report {

// A folder or file that cannot be written (the path and the system's
// reason).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writes text to a temporary name beside `path`, then renames. A failure
// (a full disk, a read-only folder) removes the temporary file and throws
// OutputError with the system's reason.
void WriteTextAtomically(const std::string& path, const std::string& text);

// Creates the directory (and parents); OutputError on failure.
void EnsureDirectory(const std::string& path);

// Everything one command writes into an output folder, written first into
// a hidden staging folder inside it and moved into place by Commit: a run
// that fails leaves nothing new (the destructor removes the staging).
class StagedOutput {
 public:
  // `command` names the run in the folder's manifest (RecordOutputs).
  StagedOutput(std::string out, std::string command);
  ~StagedOutput();
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;
  // The folder to write into now.
  const std::string& dir() const { return staging_; }
  // The final folder.
  const std::string& out() const { return out_; }
  // Moves every file of the staging folder (and its sub-folders) into the
  // final folder, replacing files of the same name; removes the files an
  // earlier wearscar run wrote there that this one did not (RecordOutputs).
  // Returns the number of files written.
  size_t Commit();
  // A path under dir() as it will be after Commit.
  std::string Final(const std::string& staged_path) const;

 private:
  std::string out_, command_, staging_;
};

// A lock on an output folder for the life of the object (flock on
// <out>/.wearscar.lock; released when the process ends, however it ends).
// kExclusive: one writer; a second fails at once with a clear message.
// kShard: the shards of one audit share the folder (each writes only its
// specimens' folders), and an exclusive writer is refused while they run.
// kMerge: waits its turn on <out>/.wearscar.merge.lock (the shards' parts,
// summaries and report are written one shard at a time).
// Where the file system refuses flock (ENOLCK, ENOSYS, EOPNOTSUPP: Lustre
// mounted noflock) this is said on stderr and the lock is taken with files
// created with O_EXCL that name their holder; such a file left by a
// wearscar that was killed is reported as stale, and `break_lock` removes
// it (and any lock file in the way).
class OutputLock {
 public:
  enum Mode { kExclusive, kShard, kMerge };
  explicit OutputLock(const std::string& out,
                      Mode mode = kExclusive,
                      bool break_lock = false);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  int fd_ = -1;
  std::string lock_file_;  // the O_EXCL file held, without flock
};

// Keeps <out>/.wearscar-manifest, the list of what wearscar wrote in a
// folder and which command wrote it (relative paths; a folder written by
// wearscar ends with '/'). With remove_stale, what the same command wrote
// there before and `entries` does not name is removed (a folder only when
// it has a manifest of its own); what another command wrote (the
// simulated inputs a fuse reads from the same folder) and files wearscar
// did not write are never touched. Without remove_stale nothing is
// removed and the lists are merged (an audit shard adds to the folder).
void RecordOutputs(const std::string& out,
                   const std::string& command,
                   std::vector<std::string> entries,
                   bool remove_stale);

}  // namespace wearscar::report
