#pragma once
// The data rows into columns, in N, mm and s on one clock. Ordinary rows
// go a fast path; anything unusual the careful way, which also joins
// restarted clocks (Rtec RecipeSteps, Bruker/CETR repeated blocks) and
// tells bad rows inside the data (an error, or dropped when lenient) from
// a text footer.

#include <Eigen/Core>
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "clock.h"
#include "columns.h"
#include "layout_detection.h"
#include "line_source.h"
#include "plausibility.h"
#include "wearscar/force/force_record.h"
#include "wearscar/force/read_force.h"
#include "wearscar/support/numbers.h"
#include "wearscar/support/prefault.h"

namespace wearscar::force::internal {

// The rows the columns have room for before they grow, and how many of
// them are mapped ahead of the parsing (those the file surely fills).
struct RowRoom {
  Eigen::Index capacity = 16;
  Eigen::Index mapped = 0;
};

class RowReader {
 public:
  // Everything is borrowed and must outlive the reader; `header_text` is
  // the header row (null: none).
  RowReader(const Layout& layout,
            const std::string* header_text,
            const Columns& column,
            int step_column,
            const Clock& clock,
            const Scale* scale,
            const ReadForceOptions& options,
            const std::string& name,
            const RowRoom& room,
            ForceMetadata* meta);

  // One line of the data (1-based `line_no` for messages).
  void Handle(std::string_view row, long line_no);

  // After the last row: the bad rows left are a footer, an error or
  // dropped; the counts are checked. Returns the columns, trimmed.
  std::array<Eigen::VectorXd, kChannels> Finish();

  // The two-thread split (split_read.cc). The ordinary rows of a stretch
  // of the file parsed on their own, and what joining them needs.
  struct FastRows {
    Eigen::Index rows = 0;           // stored from the row they were parsed to
    std::uintmax_t next_offset = 0;  // the first line not taken
    double first_time = support::kNaN, last_time = support::kNaN;
    double last_dt = support::kNaN;  // between their last two finite times
    double last_step = support::kNaN;
    int leading_nan[kChannels] = {}, trailing_nan[kChannels] = {};
  };
  // The columns as they are before the first row is read: the first
  // thread's rows stay below the second's, short of this capacity, so it
  // never grows them while the second writes.
  struct Room {
    double* column[kChannels] = {};
    Eigen::Index capacity = 0;
  };
  Room Reserved();
  // Parses the lines of `source` into the columns from row `at` on, as
  // TryFast and Store would take them one after another, up to the first
  // line they would not take on their own (a row for the careful path, a
  // step back in time, a run of missing values beyond the bound) or the
  // end. Reads only what no row changes; writes only rows from `at` on.
  FastRows ParseFastRows(FileLines& source, Eigen::Index at, const Room& room);
  // Takes those rows as the rows after the ones Handle has read when one
  // pass would have read them the same (nothing pending, no clock joined,
  // time advancing and the gaps bounded across the join), moving them to
  // follow; returns false, changing nothing, otherwise.
  bool AdoptFastRows(const FastRows& f, Eigen::Index at);

 private:
  static constexpr int kStepSlot = kChannels, kFirstSlot = kChannels + 1;

  bool TryFast(std::string_view row, long line_no);
  bool SkipRepeatedBlock(std::string_view row);
  std::string ParseCells(double* value, bool* text_row, long line_no);
  std::string JoinClock(double* value, long line_no);
  void DropPending();
  void Store(const double* values, long line_no);

  const Layout& layout_;
  const std::string* header_text_;
  const Columns column_;
  const int step_column_;
  const Clock clock_;
  const Scale* scale_;
  const ReadForceOptions& options_;
  const std::string& name_;
  ForceMetadata* meta_;
  const std::size_t columns_;
  const int needed_;
  std::vector<int> slot_of_field_;
  bool fast_possible_ = false;

  std::array<Eigen::VectorXd, kChannels> data_;
  // Maps the columns' pages beside the parsing; stopped before they grow
  // or are trimmed (and, declared after them, destroyed before them).
  support::BackgroundPrefault prefault_;
  Eigen::Index rows_stored_ = 0;
  std::vector<std::string_view> cells_;
  std::string pending_error_;
  int pending_bad_rows_ = 0, dropped_ = 0, footer_rows_ = 0, total_rows_ = 0;
  bool pending_short_ = false;  // the first pending bad row has few fields
  double previous_time_;
  double time_offset_ = 0.0, last_dt_ = 0.0, previous_step_;
  bool in_repeated_header_ = false, block_restart_ = false;
  int nan_run_[kChannels] = {};
};

}  // namespace wearscar::force::internal
