#pragma once
// What a test's result rests on that its files did not state
// (TestResult::assumptions), where the spring came from, and the test
// conditions a file states that its data contradict.

#include <string>
#include <vector>

#include "wearscar/fusion/result.h"

namespace wearscar::fusion {

// Where the spring's stiffness used came from, in words: "given", "the
// force file states", "assumed (the default: not given)".
std::string SpringOrigin(const FuseOptions& o);

// The spring, the slope judged, the reading and the running-in, in words.
std::vector<std::string> Assumptions(const force::ForceRecord& record,
                                     const TestResult& r,
                                     const FuseOptions& o);

// The conditions the file's header states that the data contradict by
// more than 10% (and a stated spring that could not be used).
std::vector<std::string> StatedButNotFound(const force::ForceRecord& record,
                                           const ForceAnalysis& force);

}  // namespace wearscar::fusion
