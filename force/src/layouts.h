#pragma once
// What wearscar knows of the tribometers' exports, as data: the layouts it
// names (layouts.cc, kLayouts), the column names that mean each channel
// (kColumnPatterns) and the column that lets a clock restart. The reader
// (read_force.cc) is the one core that detects delimiters, headers, units
// and clocks for every layout; adding an instrument is a line in
// layouts.cc (its rule, and its column words if they are new).

#include <string>

namespace wearscar::force::internal {

enum Channel { kTime = 0, kX = 1, kQ = 2, kP = 3 };

// What the layout detection found in a file's head, for the rules.
struct LayoutFacts {
  char delimiter = ',';
  bool units_row = false;
  double metadata_rate_hz = 0;  // a rate stated above the data, or 0
  std::string names;            // column names, lower case, '|' after each
  std::string units;            // their units, the same way
};

// The name of the first layout whose rule matches ("rtec", "bruker",
// "anton-paar", "home-built"), else "delimited". Information for the
// record only: every layout is read by the same core.
std::string LayoutKind(const LayoutFacts& facts);

// How well a column name means a channel: 0 no, 1-3 better.
int MatchScore(Channel channel, const std::string& name);

// A friction coefficient the instrument computed (COF, mu): never a channel.
bool IsComputedCoefficient(const std::string& name);

// A column whose change lets the clock restart (Rtec's RecipeStep).
bool IsStepColumn(const std::string& name);

}  // namespace wearscar::force::internal
