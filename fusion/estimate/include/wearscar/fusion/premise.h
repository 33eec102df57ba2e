#pragma once
// What a rule rests on, checked on the data (Ceres' Summary style: a rule
// says how it ended instead of returning a number regardless). A rule
// whose premise fails abstains and says which premise and what would
// decide; result.json lists every rule's premises beside given/used.

#include <string>
#include <vector>

namespace wearscar::fusion {

struct Premise {
  enum class State { kNotChecked, kHeld, kFailed };
  std::string rule;       // "spring check", "screen", "scan identity"
  std::string statement;  // "the groove changes during the record"
  State state = State::kNotChecked;
  std::string evidence;  // the figure the check read, in words
  // When it fails: what the rule does instead and what would decide.
  std::string otherwise;

  bool Held() const { return state == State::kHeld; }
  bool Failed() const { return state == State::kFailed; }
  const char* StateName() const;  // "held", "failed", "not checked"
};

}  // namespace wearscar::fusion
