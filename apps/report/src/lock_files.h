#pragma once

#include <string>

namespace wearscar::report::internal {

// The lock of an output folder where the file system refuses flock (a
// Lustre mount with noflock, some NFS): files created with O_EXCL that
// name their holder ("host pid time"). Exclusive: <out>/.wearscar.lock.held,
// refused while it or a shard's file exists. Shard: one file per shard,
// <out>/.wearscar.lock.shard-<host>-<pid>, refused while an exclusive one
// is held. Merge: <out>/.wearscar.merge.lock.held, waited for. A file whose
// holder ran on this host and is gone is stale: reported, and removed only
// with `break_lock` (as is a live-looking one on another host, which this
// host cannot check). Returns the file to remove when the lock ends.
enum class LockFileMode { kExclusive, kShard, kMerge };
std::string TakeLockFile(const std::string& out,
                         LockFileMode mode,
                         bool break_lock);

}  // namespace wearscar::report::internal
