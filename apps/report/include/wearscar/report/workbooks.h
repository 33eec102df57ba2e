#pragma once

// The batch's tables in the formats a lab opens: an Excel workbook of one
// or more sheets (summary.xlsx, groups.xlsx), and CSV in a locale's
// convention (--csv-locale de: semicolons and decimal commas, as a German
// Excel reads them).

#include <string>
#include <vector>

namespace wearscar::report {

// One sheet from wearscar's own CSV text (a header line, RFC 4180 cells):
// numbers as numbers, the rest as text, the header bold and frozen.
struct Sheet {
  std::string name;
  std::string csv;
};

// Writes the workbook beside `path` and renames it into place; OutputError
// naming the file when it cannot be written.
void WriteWorkbook(const std::string& path, const std::vector<Sheet>& sheets);

// RFC 4180 rows of a CSV text (quoted cells may hold commas, quotes and
// line breaks).
std::vector<std::vector<std::string>> ParseCsv(const std::string& text);

// The CSV text in `locale`'s convention: "" or "c" as it is; "de" (any
// other: the same) semicolons between cells and a decimal comma in
// numbers.
std::string LocaleCsv(const std::string& csv, const std::string& locale);

}  // namespace wearscar::report
