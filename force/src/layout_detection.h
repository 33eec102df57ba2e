#pragma once
// The layout of a delimited export from its first lines: delimiter,
// decimal mark, header and units rows, the first data row, a sampling rate
// stated above the data, and the registry's name for it.

#include <string>
#include <vector>

#include "wearscar/force/layouts.h"
#include "wearscar/force/read_force.h"

namespace wearscar::force::internal {

struct Layout {
  char delimiter = ',';
  char decimal = '.';
  int header_line = -1;  // index into head lines, -1 = no header
  int units_line = -1;
  int first_data_line = 0;
  std::vector<std::string> names;  // per column
  std::vector<std::string> units;  // per column ("" unknown)
  double metadata_rate_hz = 0.0;
  std::vector<StatedFact> stated;     // test conditions stated above the data
  const ForceLayout* kind = nullptr;  // the registry's entry
  // The first column holding a number in the first data row (0 but where
  // a text column, a status or a time of day, comes first): a row whose
  // cell there is text is a text line (a footer, a block's header).
  int first_number_column = 0;
};

// A unit cell of a units row: "(N)", "[mm]", "mm/sec", "%", ...
bool LooksLikeUnit(std::string_view cell);

// The layout of the head lines of `name`. Throws ForceError when no data
// rows are found.
Layout DetectLayout(const std::vector<std::string>& head,
                    const std::string& name,
                    const ReadForceOptions& options);

}  // namespace wearscar::force::internal
