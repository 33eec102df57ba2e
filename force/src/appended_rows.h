#pragma once
// Rows appended to a file already read (ForceFollower): read in the units
// its first rows were, P's sign as there; the checks of a whole record
// (plausibility, the channels' roles) are the whole record's.

#include <memory>
#include <string>

#include "wearscar/force/force_record.h"
#include "wearscar/force/read_force.h"

namespace wearscar::force::internal {

// What the header decided (the layout, the columns, the clock, the units),
// kept from one look's rows to the next: a file's layout does not change
// as it grows, and finding it again took a tenth of following it.
struct ReadPlan;
using KeptPlan = std::shared_ptr<ReadPlan>;

// `text`: the file's header lines, then the rows. `first`: what reading the
// file's first rows found. `plan`: the plan kept from the last rows read
// (used), or empty (this read's kept there); nullptr: planned afresh.
ForceRecord ReadAppendedRows(const std::string& text,
                             const std::string& name,
                             const ReadForceOptions& options,
                             const ForceMetadata& first,
                             KeptPlan* plan = nullptr);

}  // namespace wearscar::force::internal
