#pragma once

// Small text helpers shared by the readers and the command line.

#include <cstddef>
#include <string>
#include <string_view>

namespace wearscar::support {

// ASCII lower case.
std::string Lower(std::string_view s);

// Without leading and trailing white space.
std::string_view Trim(std::string_view s);

// The length of the well-formed UTF-8 sequence of a printable character
// (not a C1 control) at text[i], or 0.
std::size_t PrintableUtf8Length(std::string_view text, std::size_t i);

// Up to `max` characters of a header or cell for an error message: printable
// ASCII and well-formed UTF-8 as they are ("Weg [µm]"), any other byte (a
// control, Latin-1's 0xB5, binary) as \xNN, and "..." after a cut.
std::string Printable(std::string_view text, std::size_t max = 40);

}  // namespace wearscar::support
