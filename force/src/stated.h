#pragma once
// Test conditions a force file's header states in words ("Track length
// 5 mm", "Cycles: 3000", "Normal load [N] = 30", "Frequency 2 Hz"): what
// the analysis checks the data against; and the loading spring's stiffness
// ("Spring stiffness [N/mm]: 25"), which the analysis uses when none is
// given.

#include <string>
#include <vector>

#include "wearscar/force/force_record.h"

namespace wearscar::force::internal {

// The facts stated in `head` lines [0, end): at most one of each kind, the
// first found, in mm, a count, N, Hz and N/mm.
std::vector<StatedFact> FindStatedFacts(const std::vector<std::string>& head,
                                        int end);

}  // namespace wearscar::force::internal
