#pragma once
// Rows appended to a file already read (ForceFollower): read in the units
// its first rows were, P's sign as there; the checks of a whole record
// (plausibility, the channels' roles) are the whole record's.

#include <string>

#include "wearscar/force/force_record.h"
#include "wearscar/force/read_force.h"

namespace wearscar::force::internal {

// `text`: the file's header lines, then the rows. `first`: what reading the
// file's first rows found.
ForceRecord ReadAppendedRows(const std::string& text,
                             const std::string& name,
                             const ReadForceOptions& options,
                             const ForceMetadata& first);

}  // namespace wearscar::force::internal
