#pragma once

namespace wearscar::fusion {

// Silences the solver libraries' own logging (Ceres writes through glog:
// "Error in evaluating the ResidualBlock", "Logging before
// InitGoogleLogging"). wearscar reports numerical trouble in its summaries;
// a program that wants glog's lines does not call this. Idempotent.
void QuietSolverLogging();

}  // namespace wearscar::fusion
