// A table of a test's products as CSV (table.h).

#include "wearscar/fusion/table.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "wearscar/support/text.h"

namespace wearscar::fusion {

std::string Table::ToCsv() const { return ToCsv(0, rows.size()); }

std::string Table::ToCsv(std::size_t first, std::size_t last) const {
  last = std::min(last, rows.size());
  first = std::min(first, last);
  std::string buf;
  // About a dozen characters a cell, held once: growing by doubling wrote
  // a large table's text several times into fresh pages.
  buf.reserve(12 * columns.size() * (last - first + (first == 0)));
  for (size_t c = 0; first == 0 && c < columns.size(); ++c) {
    if (c) buf.push_back(',');
    buf += columns[c];
  }
  if (first == 0) buf.push_back('\n');
  // printf's %.8g (ToCharsGeneral: the characters std::to_chars writes,
  // faster); whole numbers below 10^8 (cycles, directions, counts) as
  // integers.
  char cell[32];
  for (std::size_t i = first; i < last; ++i) {
    const std::vector<double>& row = rows[i];
    for (size_t c = 0; c < row.size(); ++c) {
      if (c) buf.push_back(',');
      const double v = row[c];
      if (!std::isfinite(v)) continue;
      const bool whole = std::abs(v) < 1e8 && v == std::trunc(v) &&
                         !(v == 0 && std::signbit(v));
      const auto r =
          whole ? std::to_chars(cell, cell + sizeof cell, static_cast<long>(v))
                : support::ToCharsGeneral(cell, cell + sizeof cell, v, 8);
      buf.append(cell, r.ptr);
    }
    buf.push_back('\n');
  }
  return buf;
}

int Table::ColumnIndex(std::string_view name) const {
  const auto it = std::find(columns.begin(), columns.end(), name);
  return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
}

}  // namespace wearscar::fusion
