#pragma once
// Which column holds which channel: the ones the options name, then the
// best match by the layouts' column words; what the method needs checked
// before any row is read.

#include <array>
#include <string>
#include <vector>

#include "clock.h"
#include "layout_detection.h"
#include "wearscar/force/read_force.h"

namespace wearscar::force::internal {

// The channels the reader fills, as indices of its columns.
enum Channel { kTime = 0, kX = 1, kQ = 2, kP = 3, kDepth = 4 };
inline constexpr int kChannels = 5;

// "time", "position x", "tangential force Q", "normal force P", "depth".
const char* ChannelLabel(Channel channel);

using Columns = std::array<int, kChannels>;  // per channel, -1 = absent

// The column of each channel: the ones the options name ("NAME" or "#3"),
// then the best match by name among the columns left. Throws ForceError
// for an option that names no column.
Columns ChooseColumns(const Layout& layout,
                      const ReadForceOptions& options,
                      const std::string& name);

// What the method needs: a reciprocating displacement and the two forces.
// Refuses a file without them, saying what it has.
void RequireChannels(const Columns& column,
                     const Layout& layout,
                     const std::string& name);

// The time column as a clock when its first data cell is a date and time
// of day or a time of day (not a number): its origin that cell's.
Clock FindClock(const std::vector<std::string>& head,
                const Columns& column,
                const Layout& layout);

// The channels' columns hold numbers (or clock readings) in the first data
// rows: a column the method would read that holds text there (a time of
// day, a status) is refused here, naming it, rather than as every row's
// error.
void RequireNumbers(const std::vector<std::string>& head,
                    const Columns& column,
                    const Layout& layout,
                    const Clock& clock,
                    const std::string& name);

// The column whose change lets the clock restart (Rtec's RecipeStep), -1
// when none.
int FindStepColumn(const Layout& layout);

}  // namespace wearscar::force::internal
