#pragma once

// Constants, and the test of a finite value, that every module spells the
// same way.

#include <cmath>
#include <limits>

namespace wearscar::support {

// A missing value (an empty cell, a gap, a bin without samples).
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kPi = 3.14159265358979323846;

// Neither NaN nor infinite, as |v| <= DBL_MAX: a comparison the compiler
// can make a select or a vector mask of, where std::isfinite keeps a
// branch (-ftrapping-math), in the loops over every sample.
inline bool Finite(double v) {
  return std::abs(v) <= std::numeric_limits<double>::max();
}

// 10^k for k = 0..22, each exact as a double: one multiplication or
// division by one rounds once (the decimal readers and writers' fast
// paths).
inline constexpr double kExactPowersOf10[] = {
    1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
    1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

}  // namespace wearscar::support
