#pragma once

#include <string>

namespace wearscar::app {

// The shard this run of `wearscar audit` processes, from --shard and
// --shard-base: "i/n" (i counted from `base`, 1 unless given), or "slurm"
// (the task of a Slurm job array: its index from SLURM_ARRAY_TASK_ID, the
// plan from the array's SLURM_ARRAY_TASK_MIN, _STEP and _COUNT). The
// first shard to run records its plan in <out>/parts/plan.json; every
// other shard and re-run follows it, so `--array=7` re-running one task
// of a 0-based array of 16 is shard 8 of 16, not shard 1 of 1. Throws
// UsageError for a spec or an index the plan does not hold.
struct ShardChoice {
  int index = 1, count = 1;   // 1-based
  std::string said;           // how the index and count were found
  bool follows_plan = false;  // the folder's, not the array's own
};
ShardChoice ChooseShard(const std::string& spec,
                        int base,
                        const std::string& out);

}  // namespace wearscar::app
