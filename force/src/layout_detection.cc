#include "layout_detection.h"

#include <fast_float/fast_float.h>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <string_view>

#include "fields.h"
#include "stated.h"
#include "units.h"
#include "wearscar/support/check.h"
#include "wearscar/support/text.h"

namespace wearscar::force::internal {
namespace {

using support::Lower;

// A data row: at least two numbers, and more numbers than text cells (a
// status or comment column the method does not use may hold text; a
// metadata line such as "Stroke,5.7,mm,Frequency,10,Hz" is not data).
bool IsNumericRow(std::string_view line,
                  char delim,
                  char decimal,
                  std::vector<std::string_view>* cells) {
  Split(line, delim, cells);
  int numeric = 0, text = 0;
  for (auto c : *cells) {
    double v;
    if (c.empty() || IsMissingMarker(c)) continue;
    if (ParseCell(c, decimal, &v)) {
      ++numeric;
    } else {
      ++text;
    }
  }
  return numeric >= 2 && text < numeric;
}

// Data rows dominate the end of the head; a delimiter that splits them into
// the same number (>= 2) of cells is the one. Tab and ';' win over ','
// because ',' may be the decimal mark in those files.
char DetectDelimiter(const std::vector<std::string>& head, int vote_lines) {
  for (char d : {'\t', ';', ','}) {
    int lines = 0, consistent = 0;
    std::size_t expected = 0;
    for (auto it = head.rbegin(); it != head.rend() && lines < vote_lines;
         ++it) {
      if (it->empty()) continue;
      ++lines;
      const std::size_t n =
          static_cast<std::size_t>(std::count(it->begin(), it->end(), d));
      if (lines == 1) expected = n;
      if (n >= 1 && n == expected) ++consistent;
    }
    if (lines > 0 && expected >= 1 && consistent * 10 >= lines * 8) return d;
  }
  return ',';
}

// A sampling rate stated in a metadata line ("Sampling frequency [Hz]:
// 200", "Data rate = 2 kHz") above line `end`; 0 when none.
double FindMetadataRate(const std::vector<std::string>& lines, int end) {
  for (int i = 0; i < end; ++i) {
    const std::string lower = Lower(lines[i]);
    const bool names_rate =
        (lower.find("sampling") != std::string::npos ||
         lower.find("sample rate") != std::string::npos ||
         lower.find("acquisition rate") != std::string::npos ||
         lower.find("data rate") != std::string::npos);
    if (!names_rate) continue;
    // The first number after the label's end (':' or '=' or delimiter).
    const std::size_t pos = lower.find_first_of(":=,;\t");
    if (pos == std::string::npos) continue;
    const char* p = lines[i].data() + pos + 1;
    const char* end_p = lines[i].data() + lines[i].size();
    while (p < end_p && !(std::isdigit(static_cast<unsigned char>(*p)))) ++p;
    double rate = 0.0;
    const auto r = fast_float::from_chars(p, end_p, rate);
    if (r.ec != std::errc() || !(rate > 0)) continue;
    const bool khz = lower.find("khz") != std::string::npos;
    return khz ? rate * 1e3 : rate;
  }
  return 0.0;
}

// The decimal mark: with ';' or tab separators, ',' when more head rows
// read as numbers with it than with '.'.
char DetectDecimal(const std::vector<std::string>& head, char delimiter) {
  if (delimiter == ',') return '.';
  std::vector<std::string_view> cells;
  int dot_rows = 0, comma_rows = 0;
  for (const auto& line : head) {
    if (IsNumericRow(line, delimiter, '.', &cells)) ++dot_rows;
    if (IsNumericRow(line, delimiter, ',', &cells)) ++comma_rows;
  }
  return comma_rows > dot_rows ? ',' : '.';
}

// Which cells of a row hold text (not a number, a gap or a missing-value
// marker), and how many cells it has (without a trailing delimiter's empty
// one): the data rows of a file share one shape, a metadata line above
// them ("Load (N),30,10", "Created,2024,05,01") does not.
std::vector<bool> ShapeOf(const std::vector<std::string_view>& cells,
                          char decimal) {
  std::vector<bool> text(CountWithoutTrailing(cells));
  double v;
  for (std::size_t c = 0; c < text.size(); ++c)
    text[c] = !cells[c].empty() && !ParseCell(cells[c], decimal, &v);
  return text;
}

// The first data row: numeric and followed by numeric rows of its shape
// (or the end).
int FindFirstDataLine(const std::vector<std::string>& head,
                      const Layout& layout,
                      const std::string& name) {
  std::vector<std::string_view> cells;
  const int n = static_cast<int>(head.size());
  for (int i = 0; i < n; ++i) {
    if (!IsNumericRow(head[i], layout.delimiter, layout.decimal, &cells))
      continue;
    const std::vector<bool> shape = ShapeOf(cells, layout.decimal);
    int ok = 1;
    for (int j = i + 1; j < std::min(n, i + 4); ++j) {
      if (IsNumericRow(head[j], layout.delimiter, layout.decimal, &cells) &&
          ShapeOf(cells, layout.decimal) == shape)
        ++ok;
    }
    if (ok >= std::min(3, n - i)) return i;
  }
  throw ForceError(fmt::format(
      "{}: no numeric data found in the first {} lines; expected rows of at "
      "least two numbers separated by '{}'",
      name,
      n,
      layout.delimiter == '\t' ? "\\t" : std::string(1, layout.delimiter)));
}

// The header above the data, possibly with a units row between.
void FindHeaderAndUnits(const std::vector<std::string>& head, Layout* layout) {
  std::vector<std::string_view> cells;
  int above = layout->first_data_line - 1;
  while (above >= 0 && TrimView(head[above]).empty()) --above;
  if (above >= 0) {
    Split(head[above], layout->delimiter, &cells);
    const bool all_units =
        cells.size() >= 2 &&
        std::all_of(cells.begin(), cells.end(), LooksLikeUnit) &&
        std::any_of(cells.begin(), cells.end(), [](std::string_view c) {
          return !c.empty();
        });
    if (all_units && above >= 1) {
      layout->units_line = above;
      --above;
      while (above >= 0 && TrimView(head[above]).empty()) --above;
    }
  }
  if (above >= 0) {
    Split(head[above], layout->delimiter, &cells);
    if (cells.size() >= 2) layout->header_line = above;
  }
  if (layout->header_line < 0) layout->units_line = -1;
}

// Column names and units from the header ("Fx (N)") and the units row.
void ReadNamesAndUnits(const std::vector<std::string>& head, Layout* layout) {
  std::vector<std::string_view> cells;
  Split(head[layout->header_line >= 0 ? layout->header_line
                                      : layout->first_data_line],
        layout->delimiter,
        &cells);
  const std::size_t columns = CountWithoutTrailing(cells);
  layout->names.assign(columns, "");
  layout->units.assign(columns, "");
  if (layout->header_line >= 0) {
    Split(head[layout->header_line], layout->delimiter, &cells);
    for (std::size_t c = 0; c < std::min(columns, cells.size()); ++c)
      SplitNameAndUnit(cells[c], &layout->names[c], &layout->units[c]);
  }
  if (layout->units_line >= 0) {
    Split(head[layout->units_line], layout->delimiter, &cells);
    for (std::size_t c = 0; c < std::min(columns, cells.size()); ++c) {
      std::string unit_name, unit;
      SplitNameAndUnit(cells[c], &unit_name, &unit);
      const std::string u = unit.empty() ? unit_name : unit;
      if (!u.empty()) layout->units[c] = u;
    }
  }
}

// The registry's layout for what was found.
const ForceLayout& KindOf(const Layout& layout) {
  LayoutFacts facts;
  facts.delimiter = layout.delimiter;
  facts.units_row = layout.units_line >= 0;
  facts.metadata_rate_hz = layout.metadata_rate_hz;
  for (const auto& n : layout.names) facts.names.push_back(Lower(n));
  for (const auto& u : layout.units) facts.units.push_back(Lower(u));
  return DetectForceLayout(facts);
}

}  // namespace

bool LooksLikeUnit(std::string_view cell) {
  if (cell.empty()) return true;
  if ((cell.front() == '(' && cell.back() == ')') ||
      (cell.front() == '[' && cell.back() == ']')) {
    return true;
  }
  auto simple = [](std::string_view u) {
    const std::string l = Lower(u);
    return LengthToMm(u) || ForceToN(u) || TimeToS(u) || l == "hz" ||
           l == "c" ||
           l == "\xb0"
                "c" ||
           l == "\xc2\xb0"
                "c" ||
           l == "%" || l == "-" || l == "()" || l == "deg" || l == "rpm" ||
           l == "v" || l == "mv" || l == "um" || l == "n/a" || l == "cycles" ||
           l == "cycle";
  };
  if (simple(cell)) return true;
  // Rates and ratios: "mm/sec" (CETR), "mm/s", "N/mm", "g/cm".
  const std::size_t slash = cell.find('/');
  return slash != std::string_view::npos && slash > 0 &&
         simple(cell.substr(0, slash)) && simple(cell.substr(slash + 1));
}

Layout DetectLayout(const std::vector<std::string>& head,
                    const std::string& name,
                    const ReadForceOptions& options) {
  // ReadHead refuses an empty file.
  WEARSCAR_CHECK(!head.empty(), "DetectLayout needs the head lines");
  Layout layout;
  layout.delimiter = DetectDelimiter(head, options.delimiter_vote_lines);
  layout.decimal = DetectDecimal(head, layout.delimiter);
  layout.first_data_line = FindFirstDataLine(head, layout, name);
  std::vector<std::string_view> cells;
  Split(head[layout.first_data_line], layout.delimiter, &cells);
  double v;
  while (layout.first_number_column + 1 < static_cast<int>(cells.size()) &&
         !ParseCell(cells[layout.first_number_column], layout.decimal, &v))
    ++layout.first_number_column;
  FindHeaderAndUnits(head, &layout);
  ReadNamesAndUnits(head, &layout);
  const int above =
      layout.header_line >= 0 ? layout.header_line : layout.first_data_line;
  layout.metadata_rate_hz = FindMetadataRate(head, above);
  layout.stated = FindStatedFacts(head, above);
  layout.kind = &KindOf(layout);
  return layout;
}

}  // namespace wearscar::force::internal
