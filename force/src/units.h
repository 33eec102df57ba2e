#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace wearscar::force::internal {

// Multiplier from a unit as written in an export to the library unit, or
// nullopt when the unit is not one of that quantity. Case matters only where
// it must ("mN" vs "MN" never occurs in tribometer exports; "m" is metres).
std::optional<double> LengthToMm(std::string_view unit);
std::optional<double> ForceToN(std::string_view unit);
std::optional<double> TimeToS(std::string_view unit);

// "DAQ.Fz (N)" -> name "DAQ.Fz", unit "N"; "Time [s]" -> "Time", "s".
void SplitNameAndUnit(std::string_view header,
                      std::string* name,
                      std::string* unit);

}  // namespace wearscar::force::internal
