#pragma once

#include <stdexcept>

namespace wearscar::app {

// Thrown for bad command-line input (and bad keyword arguments in Python);
// main maps it to exit status 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace wearscar::app
