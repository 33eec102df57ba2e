#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "wearscar/samples/virtual_tribometer.h"

namespace wearscar::fusion {

// The paper's 12 cases, for the parameterised suites.
inline std::vector<std::string> TwelveCases() {
  std::vector<std::string> names;
  for (const auto& o : samples::PaperCases()) names.push_back(o.name);
  return names;
}

// "B-RT-R" -> "B_RT_R": a GoogleTest parameter name.
inline std::string TestName(std::string case_name) {
  std::replace(case_name.begin(), case_name.end(), '-', '_');
  return case_name;
}

}  // namespace wearscar::fusion
