#pragma once

#include <stdexcept>

namespace wearscar::fusion {

// Raised for bad user input to the fusion stage (mismatched inputs, options
// out of range); numerical failures go in the summaries instead.
class FusionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace wearscar::fusion
