#pragma once

// Constants every module spells the same way.

#include <limits>

namespace wearscar::support {

// A missing value (an empty cell, a gap, a bin without samples).
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kPi = 3.14159265358979323846;

}  // namespace wearscar::support
