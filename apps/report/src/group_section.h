#pragma once
// The audit report's section on the batch's groups and factors
// (fusion::CompareGroups): tables, a figure, the planning line.

#include <string>
#include <vector>

#include "wearscar/fusion/groups.h"

namespace wearscar::report::internal {

// "" when there is nothing to show.
std::string GroupSection(const std::vector<fusion::GroupComparison>& groups);

}  // namespace wearscar::report::internal
