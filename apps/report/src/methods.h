#pragma once
// The methods paragraph of an audit (methods.md): what was done to the
// batch, with which options and version, in words a reviewer reads.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "wearscar/fusion/groups.h"

namespace wearscar::report::internal {

// From the batch's summary rows (result.json with identity) and its group
// comparison; Markdown.
std::string MethodsText(const std::vector<nlohmann::json>& rows,
                        const std::vector<fusion::GroupComparison>& groups);

// references.bib: the method's paper and the wearscar build of `rows`.
std::string References(const std::vector<nlohmann::json>& rows);

}  // namespace wearscar::report::internal
