#include "stated.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>

#include "wearscar/support/text.h"

namespace wearscar::force::internal {
namespace {

// A label, the fact it names and the factor from its value to the fact
// (an amplitude is half the stroke).
struct Label {
  const char* words;
  const char* what;
  double factor;
};

// Longer labels first, so that "normal load" is found before "load".
constexpr Label kLabels[] = {
    {"stroke length", "stroke", 1},
    {"track length", "stroke", 1},
    {"stroke", "stroke", 1},
    {"amplitude", "stroke", 2},
    {"number of cycles", "cycles", 1},
    {"cycles", "cycles", 1},
    {"laps", "cycles", 1},
    {"normal load", "load", 1},
    {"applied load", "load", 1},
    {"normal force", "load", 1},
    {"load", "load", 1},
    {"frequency", "frequency", 1},
    {"spring stiffness", "spring", 1},
    {"spring constant", "spring", 1},
    {"spring rate", "spring", 1},
    {"loading spring", "spring", 1},
    // A rotary (pin-on-disk) test's track radius: not a reciprocating test.
    {"track radius", "radius", 1},
    {"radius", "radius", 1},
};

// The factor of the unit written near the number (before it in brackets,
// or after it), into mm, N, Hz or N/mm; 1 when none is written.
double UnitFactor(const std::string& what, const std::string& near) {
  auto has = [&](const char* u) {
    const std::string unit(u);
    for (size_t at = near.find(unit); at != std::string::npos;
         at = near.find(unit, at + 1)) {
      const bool left =
          at == 0 || !std::isalpha(static_cast<unsigned char>(near[at - 1]));
      const size_t after = at + unit.size();
      const bool right = after >= near.size() ||
                         !std::isalpha(static_cast<unsigned char>(near[after]));
      if (left && right) return true;
    }
    return false;
  };
  if (what == "stroke" || what == "radius") {
    if (has("um") || has("\xc2\xb5m") || has("micron")) return 1e-3;
    if (has("cm")) return 10;
    if (has("mm")) return 1;
    if (has("m")) return 1e3;
  } else if (what == "load") {
    if (has("mn")) return 1e-3;
    if (has("kn")) return 1e3;
  } else if (what == "frequency") {
    if (has("khz")) return 1e3;
  } else if (what == "spring") {  // into N/mm
    if (has("n/um") || has("n/\xc2\xb5m")) return 1e3;
    if (has("kn/m")) return 1;
    if (has("n/m")) return 1e-3;
  }
  return 1;
}

// Where `words` stand as words in `lower` (not inside "elapsed" or
// "loaded"), or npos.
size_t FindWord(const std::string& lower, const std::string& words) {
  for (size_t at = lower.find(words); at != std::string::npos;
       at = lower.find(words, at + 1)) {
    const size_t after = at + words.size();
    const bool left =
        at == 0 || !std::isalpha(static_cast<unsigned char>(lower[at - 1]));
    const bool right = after >= lower.size() ||
                       !std::isalpha(static_cast<unsigned char>(lower[after]));
    if (left && right) return at;
  }
  return std::string::npos;
}

// The unit written right after a number ("" for none), with its space.
std::string UnitAfter(const std::string& line, size_t after) {
  size_t from = after;
  while (from < line.size() && line[from] == ' ') ++from;
  size_t end = from;
  while (end < line.size() && line[end] != ' ' && line[end] != ',' &&
         line[end] != ';' && line[end] != '\t' && line[end] != '\r')
    ++end;
  const std::string word = support::Lower(line.substr(from, end - from));
  static const char* const kUnits[] = {"mm",
                                       "um",
                                       "\xc2\xb5m",
                                       "cm",
                                       "m",
                                       "n",
                                       "mn",
                                       "kn",
                                       "hz",
                                       "khz",
                                       "n/mm",
                                       "n/m",
                                       "kn/m",
                                       "n/um",
                                       "cycles"};
  for (const char* u : kUnits)
    if (word == u) return line.substr(after, end - after);
  return "";
}

// A radius of the ball, pin or tip, not of a rotary test's track.
bool NamesTheCounterpart(const std::string& lower, size_t label_at) {
  const std::string before = lower.substr(0, label_at);
  for (const char* w : {"ball",
                        "sphere",
                        "pin",
                        "tip",
                        "counterbody",
                        "counterpart",
                        "indenter",
                        "probe"}) {
    if (before.find(w) != std::string::npos) return true;
  }
  return false;
}

// The frequency of the drive, not of the sampling.
bool NamesTheSampling(const std::string& lower, size_t label_at) {
  const std::string before = lower.substr(0, label_at);
  for (const char* w : {"sampling", "acquisition", "data", "sample"}) {
    if (before.find(w) != std::string::npos) return true;
  }
  return false;
}

}  // namespace

std::vector<StatedFact> FindStatedFacts(const std::vector<std::string>& head,
                                        int end) {
  std::vector<StatedFact> facts;
  auto known = [&](const std::string& what) {
    return std::any_of(facts.begin(), facts.end(), [&](const StatedFact& f) {
      return f.what == what;
    });
  };
  for (int i = 0; i < end && i < static_cast<int>(head.size()); ++i) {
    const std::string lower = support::Lower(head[i]);
    for (const Label& l : kLabels) {
      const size_t at = FindWord(lower, l.words);
      if (at == std::string::npos || known(l.what)) continue;
      if (std::string(l.what) == "frequency" && NamesTheSampling(lower, at))
        continue;
      if (std::string(l.what) == "load" &&
          lower.find("load cell") != std::string::npos)
        continue;
      // The counterpart's radius (a ball's) says nothing of the track.
      if (std::string(l.what) == "radius" && NamesTheCounterpart(lower, at))
        continue;
      // The first number within 40 characters after the label.
      const size_t from = at + std::string(l.words).size();
      const size_t digit = lower.find_first_of("0123456789", from);
      if (digit == std::string::npos || digit - from > 40) continue;
      const char* start = lower.c_str() + digit;
      char* stop = nullptr;
      const double value = std::strtod(start, &stop);
      if (!(value > 0)) continue;
      const size_t after = static_cast<size_t>(stop - lower.c_str());
      const std::string near =
          lower.substr(from, digit - from) + " " + lower.substr(after, 8);
      StatedFact f;
      f.what = l.what;
      f.value = value * l.factor * UnitFactor(f.what, near);
      // Quoted as written from its label to its number and the unit after
      // it (a header line may hold several facts: "Track length [mm]: 5
      // Cycles: 600").
      f.line = head[i].substr(at, after - at) + UnitAfter(head[i], after);
      f.line_number = i + 1;
      facts.push_back(f);
    }
  }
  return facts;
}

}  // namespace wearscar::force::internal
