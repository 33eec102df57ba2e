#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "wearscar/fusion/table.h"

namespace wearscar::fusion {

// Every table of one test's products (MakeTestProducts), in the order
// they are written: the products' own, then the analysis units' (in the
// registry's order); those that need a scan, or a unit that did not run,
// are left out of a test without.
const std::vector<TableSchema>& TestTableSchemas();

// The columns of the table `file` of TestTableSchemas() (the residual
// maps of a diagnosis too); empty for a file that is not one.
const std::vector<std::string>& TableColumns(std::string_view file);

// The columns of cycles.csv.
const std::vector<std::string>& CycleColumns();

}  // namespace wearscar::fusion
