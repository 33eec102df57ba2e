#pragma once
// Figures as data: a figure is panels of series, each series two or more
// columns of a table named by their names (the tables' column lists are
// fusion::TableColumns), so that adding a figure is one entry of a list.
// Draw writes each figure's data (the columns it plots, one block per
// series) into figure-data/<figure>.csv, one gnuplot script for all of
// them, and runs gnuplot once.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "images.h"
#include "wearscar/fusion/tables.h"
#include "wearscar/report/figures.h"

namespace wearscar::report::internal {

// Colours by role, the same in every figure and in the report's loop
// viewer: the force side's slope (k from P) blue, the scan's orange,
// measured data black, the classic COFs green, thresholds red; the
// direction by the dash: forward solid, reverse dashed.
inline constexpr const char* kForceColour = "#1f77b4";
inline constexpr const char* kScanColour = "#ff7f0e";
inline constexpr const char* kMeasuredColour = "#000000";
inline constexpr const char* kClassicColour = "#2ca02c";
inline constexpr const char* kLimitColour = "#d62728";

// One line, set of points or band of a plot: columns of a table by name.
struct Series {
  Series() = default;
  Series(std::string table_name,
         std::string x_column,
         std::string y_column,
         std::string key_title = "",
         std::vector<std::string> more_columns = {})
      : table(std::move(table_name)),
        x(std::move(x_column)),
        y(std::move(y_column)),
        more(std::move(more_columns)),
        title(std::move(key_title)) {}

  std::string table;              // a table's file name ("detail.csv")
  std::string x, y;               // its columns
  std::vector<std::string> more;  // columns after y (a band's upper edge)
  std::string title;              // the key's entry; "" none
  std::string style = "lines";    // what follows gnuplot's `with`
  // Only the rows whose column `select` holds `select_value`.
  std::string select;
  double select_value = 0;
  // The line broken (a blank line in the data) where this column's value
  // changes: no line joins two sliding directions or two cycles.
  std::string break_at;
  // Drawn as y_scale * y + y_offset.
  double y_scale = 1, y_offset = 0;
  // Instead of a table: a gnuplot expression in x (a constant line).
  std::string function;
};

struct Panel {
  std::string title, xlabel, ylabel;
  std::string setup;  // gnuplot commands before the plot (ranges, marks)
  std::optional<Image> image;  // drawn first, the series over it
  std::string cblabel;         // the image's colour bar
  std::vector<Series> series;
};

struct FigureSpec {
  std::string stem, title;
  std::vector<Panel> panels;  // more than one: stacked top to bottom
  int columns = 1;            // or in a grid of this many columns
};

// The tables figures read, by file name.
using TableSet = std::map<std::string, const fusion::Table*>;

// Draws `figures` into `dir` in each format asked for, from `tables`. Each
// figure is drawn under a temporary name and renamed into place only when
// it is there, not empty and of its format: a killed or failed gnuplot
// leaves no half figure; what was not drawn is in the set's `missing`,
// with a message.
FigureSet Draw(const std::string& dir,
               const std::vector<FigureSpec>& figures,
               const TableSet& tables,
               const FigureFormats& formats);

// Runs gnuplot on <dir>/figure-data/<script> in `dir` and waits; its
// output goes to figure-data/<stem>.log. False when it failed.
bool RunGnuplot(const std::string& dir, const std::string& script);

// The `set terminal` line of a figure in format "svg" or "png" with
// `rows` rows of panels: every figure's canvas and text size.
std::string Terminal(const std::string& term, int rows);

// A gnuplot string literal.
std::string Quote(const std::string& s);

}  // namespace wearscar::report::internal
