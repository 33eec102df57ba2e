#pragma once
// Fields and numbers: a delimited row split into cells (RFC 4180 quotes),
// a cell parsed as a number, a missing-value marker, and the one pass over
// an ordinary data row that parses only the fields the reader keeps.

#include <string_view>
#include <vector>

#include "clock.h"

namespace wearscar::force::internal {

// Without blanks (space, tab) at either end and one pair of enclosing
// double quotes.
std::string_view TrimView(std::string_view s);

// Splits `line` on `delim` into `cells` (views into line), cells trimmed,
// by RFC 4180: a cell in double quotes may hold the delimiter ("Time, s");
// its view keeps a doubled quote as two characters.
void Split(std::string_view line,
           char delim,
           std::vector<std::string_view>* cells);

// Cells of a row without the empty cell a trailing delimiter adds (Rtec
// ends every row with one).
std::size_t CountWithoutTrailing(const std::vector<std::string_view>& cells);

// The markers spreadsheets and programs write for a missing value: Excel's
// "#N/A" ("#NV" in German), R's "NA", "N/A", "null", and the NaN of
// Microsoft's C library ("-nan(ind)", and "1.#QNAN", "-1.#IND" of older
// ones) in a home-built rig's log (any case).
bool IsMissingMarker(std::string_view cell);

// Parses a whole cell as a number. Empty cell -> NaN (a gap); "nan" and the
// missing-value markers -> NaN. Returns false for text.
bool ParseCell(std::string_view cell, char decimal, double* value);

// One pass over a data row parsing only the fields that `slot_of_field`
// maps to a slot of `out` (-1: skip), trimming blanks; `clock.field`, if
// any, is read as a clock. Returns false on anything the careful path must
// look at: quotes, text, or a field count other than `slot_of_field`'s
// size (plus one empty field after a trailing delimiter).
bool FastRow(std::string_view row,
             char delim,
             char decimal,
             const std::vector<int>& slot_of_field,
             const Clock& clock,
             double* out);

}  // namespace wearscar::force::internal
