#pragma once
// Cells and numbers of the text height maps (Keyence VR CSV, ASCII
// matrices): lines, trimmed unquoted cells, numbers read whole, units.

#include <fast_float/fast_float.h>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "wearscar/support/text.h"

namespace wearscar::scan::internal {

inline std::vector<std::string_view> Lines(std::string_view text) {
  std::vector<std::string_view> lines;
  size_t pos = 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    pos = end + 1;
  }
  return lines;
}

// A cell without surrounding spaces and tabs, unquoted.
inline std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t'))
    s.remove_suffix(1);
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"')
    s = s.substr(1, s.size() - 2);
  return s;
}

inline std::vector<std::string_view> SplitCells(std::string_view line,
                                                char delim) {
  std::vector<std::string_view> cells;
  size_t start = 0;
  for (;;) {
    const size_t end = line.find(delim, start);
    cells.push_back(Trim(
        line.substr(start, end == std::string_view::npos ? end : end - start)));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  return cells;
}

inline std::optional<double> Number(std::string_view cell, char decimal) {
  if (cell.empty()) return std::nullopt;
  if (cell.front() == '+') cell.remove_prefix(1);
  double v;
  const auto r = fast_float::from_chars_advanced(
      cell.data(),
      cell.data() + cell.size(),
      v,
      fast_float::parse_options{fast_float::chars_format::general, decimal});
  if (r.ec != std::errc() || r.ptr != cell.data() + cell.size())
    return std::nullopt;
  return v;
}

using support::Lower;

// "um", "µm" (UTF-8 or Latin-1), "μm", Shift-JIS "μm" (0x83 0xCA 'm').
inline bool IsMicrometre(std::string_view u) {
  const std::string l = Lower(Trim(u));
  return l == "um" || l == "\xc2\xb5m" || l == "\xce\xbcm" || l == "\xb5m" ||
         l == "\x83\xca"
              "m" ||
         l == "micrometer" || l == "micrometre";
}

inline std::optional<double> UnitToMm(std::string_view u) {
  const std::string l = Lower(Trim(u));
  if (IsMicrometre(u)) return 1e-3;
  if (l == "mm") return 1.0;
  if (l == "nm") return 1e-6;
  if (l == "m") return 1e3;
  return std::nullopt;
}

}  // namespace wearscar::scan::internal
