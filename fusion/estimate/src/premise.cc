#include "wearscar/fusion/premise.h"

namespace wearscar::fusion {

const char* Premise::StateName() const {
  switch (state) {
    case State::kHeld:
      return "held";
    case State::kFailed:
      return "failed";
    case State::kNotChecked:
      break;
  }
  return "not checked";
}

}  // namespace wearscar::fusion
