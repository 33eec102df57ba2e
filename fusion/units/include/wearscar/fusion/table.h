#pragma once
// A table of a test's products: the analysis units write theirs, the
// products the rest (tables.h lists them all).

#include <string>
#include <string_view>
#include <vector>

namespace wearscar::fusion {

// A table of numbers whose column names carry their units ("x_mm", "Q_N",
// "mu_hat_force"); non-finite values are empty cells in CSV.
struct Table {
  Table() = default;
  explicit Table(std::vector<std::string> column_names)
      : columns(std::move(column_names)) {}
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;

  std::string ToCsv() const;
  // Rows [first, last) of ToCsv's text, with the header when first is 0:
  // the pieces of a large table, formatted apart, joined give ToCsv().
  std::string ToCsv(std::size_t first, std::size_t last) const;
  // The index of `name` among the columns, -1 when it is not one.
  int ColumnIndex(std::string_view name) const;
};

// A table a test's products may hold: its file name, its columns and what
// it is. Figures and other readers name columns from these lists.
struct TableSchema {
  std::string file;  // "detail.csv"
  std::vector<std::string> columns;
  std::string what;
};

}  // namespace wearscar::fusion
