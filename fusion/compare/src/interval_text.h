#pragma once
// The verdict's and the screen's words for a 95% interval.

#include <string>

namespace wearscar::fusion::internal {

// " (95% interval 0.012 to 0.034)" in `format`, or "" when there is none.
std::string IntervalText(double low, double high, const char* format);

}  // namespace wearscar::fusion::internal
