#pragma once

// Small text helpers shared by the readers and the command line. Private
// to wearscar's libraries (header-only, never installed).

#include <algorithm>
#include <cctype>
#include <string>
#include <string_view>

namespace wearscar::support {

// ASCII lower case.
inline std::string Lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](char c) {
    return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  });
  return out;
}

// Without leading and trailing white space.
inline std::string_view Trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\n\v\f\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\n\v\f\r");
  return s.substr(first, last - first + 1);
}

// Up to `max` bytes of a header or cell for an error message, anything not
// printable ASCII written as \xNN and "..." after a cut.
inline std::string Printable(std::string_view text, std::size_t max = 40) {
  static const char kHex[] = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < text.size() && i < max; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  if (text.size() > max) out += "...";
  return out;
}

}  // namespace wearscar::support
