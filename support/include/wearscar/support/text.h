#pragma once

// Small text helpers shared by the readers and the command line.

#include <charconv>
#include <cstddef>
#include <string>
#include <string_view>

namespace wearscar::support {

// ASCII lower case.
std::string Lower(std::string_view s);
// ASCII letters in upper case ("rt" -> "RT"); other bytes as they are.
std::string Upper(std::string_view s);

// Without leading and trailing white space.
std::string_view Trim(std::string_view s);

// The length of the well-formed UTF-8 sequence of a printable character
// (not a C1 control) at text[i], or 0.
std::size_t PrintableUtf8Length(std::string_view text, std::size_t i);

// Up to `max` characters of a header or cell for an error message: printable
// ASCII and well-formed UTF-8 as they are ("Weg [µm]"), any other byte (a
// control, Latin-1's 0xB5, binary) as \xNN, and "..." after a cut.
std::string Printable(std::string_view text, std::size_t max = 40);

// `value` as printf's %.{precision}g writes it (std::to_chars with
// chars_format::general and the precision: the same characters), for the
// tables' numbers: most values by one scaling and one rounding, exact
// where that rounding is unambiguous; near a tie of the last digit, at
// exponents beyond +-15, zero and what is not finite, by std::to_chars
// (Ryu), which takes longer. [first, last) should hold 32 characters (with
// fewer, std::to_chars writes what fits).
std::to_chars_result ToCharsGeneral(char* first,
                                    char* last,
                                    double value,
                                    int precision);

}  // namespace wearscar::support
