#include "row_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "fields.h"
#include "wearscar/support/numbers.h"
#include "wearscar/support/text.h"

namespace wearscar::force::internal {
namespace {

using support::kNaN;

}  // namespace

RowReader::RowReader(const Layout& layout,
                     const std::string* header_text,
                     const Columns& column,
                     int step_column,
                     const Clock& clock,
                     const Scale* scale,
                     const ReadForceOptions& options,
                     const std::string& name,
                     const RowRoom& room,
                     ForceMetadata* meta)
    : layout_(layout),
      header_text_(header_text),
      column_(column),
      step_column_(step_column),
      clock_(clock),
      scale_(scale),
      options_(options),
      name_(name),
      meta_(meta),
      columns_(layout.names.size()),
      needed_(*std::max_element(column.begin(), column.end())),
      slot_of_field_(columns_, -1),
      previous_time_(-std::numeric_limits<double>::infinity()),
      previous_step_(kNaN) {
  std::vector<support::BackgroundPrefault::Buffer> mapped;
  const Eigen::Index ahead = std::min(room.mapped, room.capacity);
  for (int ch = 0; ch < kChannels; ++ch) {
    if (column_[ch] < 0) continue;
    data_[ch].resize(room.capacity);
    mapped.emplace_back(data_[ch].data(),
                        sizeof(double) * static_cast<std::size_t>(ahead));
  }
  prefault_.Start(std::move(mapped));
  // Fast path slots: the four channels, the RecipeStep column, and the
  // first field that holds a number (text there means a footer or a bad
  // row).
  if (layout.first_number_column < static_cast<int>(columns_))
    slot_of_field_[layout.first_number_column] = kFirstSlot;
  for (int ch = 0; ch < kChannels; ++ch) {
    if (column_[ch] >= 0 && column_[ch] < static_cast<int>(columns_))
      slot_of_field_[column_[ch]] = ch;
  }
  if (step_column_ >= 0 && step_column_ < static_cast<int>(columns_))
    slot_of_field_[step_column_] = kStepSlot;
  fast_possible_ = needed_ < static_cast<int>(columns_);
}

void RowReader::Handle(std::string_view row, long line_no) {
  if (fast_possible_ && pending_bad_rows_ == 0 && TryFast(row, line_no)) return;
  if (TrimView(row).empty() || SkipRepeatedBlock(row)) return;
  double value[kChannels] = {kNaN, kNaN, kNaN, kNaN, kNaN};
  bool text_row = false;
  std::string error = ParseCells(value, &text_row, line_no);
  if (error.empty() && column_[kTime] >= 0) error = JoinClock(value, line_no);
  if (!error.empty()) {
    // A row with fewer fields than the header, last in the file, is a cut
    // row (an interrupted export), not a bad file (Finish).
    if (pending_bad_rows_ == 0)
      pending_short_ = !text_row && cells_.size() < columns_;
    if (pending_error_.empty()) pending_error_ = error;
    ++pending_bad_rows_;
    footer_rows_ += text_row ? 1 : 0;
    if (!text_row) footer_rows_ = -1000000;  // a numeric bad row: no footer
    return;
  }
  if (pending_bad_rows_ > 0) DropPending();
  Store(value, line_no);
}

std::array<Eigen::VectorXd, kChannels> RowReader::Finish() {
  if (pending_bad_rows_ > 0) {
    if (pending_bad_rows_ == 1 && pending_short_) {
      meta_->warnings.push_back(
          fmt::format("the last row is cut and was dropped ({}): was the "
                      "export interrupted?",
                      pending_error_.substr(name_.size() + 2)));
    } else if (footer_rows_ == pending_bad_rows_) {
      meta_->warnings.push_back(
          fmt::format("ignored a footer of {} text lines", footer_rows_));
    } else if (!options_.lenient) {
      throw ForceError(pending_error_);
    } else {
      dropped_ += pending_bad_rows_;
    }
  }
  if (total_rows_ < 2) {
    throw ForceError(fmt::format(
        "{}: only {} data rows; expected a time series", name_, total_rows_));
  }
  meta_->rows_dropped = dropped_;
  if (dropped_ > 0) {
    if (dropped_ > options_.max_dropped_fraction * (total_rows_ + dropped_)) {
      throw ForceError(fmt::format(
          "{}: {} of {} rows are bad (more than {:.1f}%); first: {}",
          name_,
          dropped_,
          total_rows_ + dropped_,
          100 * options_.max_dropped_fraction,
          meta_->warnings.empty() ? pending_error_ : meta_->warnings.front()));
    }
    meta_->warnings.push_back(fmt::format("dropped {} bad rows", dropped_));
  }
  prefault_.Stop();
  for (int ch = 0; ch < kChannels; ++ch) {
    if (column_[ch] >= 0) data_[ch].conservativeResize(rows_stored_);
  }
  return std::move(data_);
}

// The ordinary row: all fields numbers, time after the previous one.
bool RowReader::TryFast(std::string_view row, long line_no) {
  double v[kChannels + 2] = {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
  if (!FastRow(
          row, layout_.delimiter, layout_.decimal, slot_of_field_, clock_, v))
    return false;
  const bool timed = column_[kTime] >= 0;
  const double t = timed ? v[kTime] * scale_[kTime].factor + time_offset_ : 0;
  if (timed && std::isfinite(t) && t <= previous_time_) return false;
  if (timed) {
    if (std::isfinite(t)) {
      if (std::isfinite(previous_time_)) last_dt_ = t - previous_time_;
      previous_time_ = t;
    }
    v[kTime] = t;
  }
  if (step_column_ >= 0) previous_step_ = v[kStepSlot];
  Store(v, line_no);
  return true;
}

// A repeated block (Bruker/CETR: every test step repeats its header block,
// names row, units row, then data whose clock restarts): the names row
// again ends the text lines before it, which were that block's header, not
// bad rows; the text up to the next data row is skipped and the clock may
// restart once. Splits the row into cells_ otherwise.
bool RowReader::SkipRepeatedBlock(std::string_view row) {
  if (header_text_ != nullptr && TrimView(row) == TrimView(*header_text_)) {
    if (pending_bad_rows_ > 0 && footer_rows_ == pending_bad_rows_) {
      pending_error_.clear();
      pending_bad_rows_ = 0;
      footer_rows_ = 0;
    }
    in_repeated_header_ = true;
    block_restart_ = true;
    ++meta_->blocks_joined;
    return true;
  }
  Split(row, layout_.delimiter, &cells_);
  double first_cell;
  if (in_repeated_header_ && !cells_.empty() &&
      (!ParseCell(cells_[0], layout_.decimal, &first_cell) ||
       (cells_[0].empty() &&
        std::all_of(cells_.begin(), cells_.end(), LooksLikeUnit)))) {
    return true;  // the repeated block's units row
  }
  in_repeated_header_ = false;
  return false;
}

// The channels' numbers from cells_, or the error that says why not.
std::string RowReader::ParseCells(double* value, bool* text_row, long line_no) {
  double first_value;
  const std::size_t probe =
      cells_.empty()
          ? 0
          : std::min(static_cast<std::size_t>(layout_.first_number_column),
                     cells_.size() - 1);
  const bool text_first =
      !cells_.empty() && !cells_[probe].empty() &&
      !ParseCell(cells_[probe], layout_.decimal, &first_value);
  const bool trailing_ok =
      cells_.size() == columns_ + 1 && cells_.back().empty();
  if (text_first) {
    *text_row = true;
    return fmt::format(
        "{}: line {}: found text '{}' where a data row was expected",
        name_,
        line_no,
        support::Printable(cells_[0]));
  }
  if (static_cast<int>(cells_.size()) <= needed_ ||
      (cells_.size() != columns_ && !trailing_ok)) {
    return fmt::format("{}: line {}: ragged row: found {} fields, expected {}",
                       name_,
                       line_no,
                       cells_.size(),
                       columns_);
  }
  for (int ch = 0; ch < kChannels; ++ch) {
    if (column_[ch] < 0) continue;
    const std::string_view cell = cells_[column_[ch]];
    const bool ok = column_[ch] == clock_.field
                        ? ClockSeconds(clock_, cell, &value[ch])
                        : ParseCell(cell, layout_.decimal, &value[ch]);
    if (!ok) {
      return fmt::format(
          "{}: line {}, column {} ('{}'): found '{}', expected a number{}",
          name_,
          line_no,
          column_[ch] + 1,
          layout_.names[column_[ch]],
          support::Printable(cell),
          layout_.decimal == ',' ? " with a decimal comma" : "");
    }
  }
  return {};
}

// Time on the joined clock: a clock that restarts with a new RecipeStep or
// a repeated block continues; any other step back is an error.
std::string RowReader::JoinClock(double* value, long line_no) {
  double t = value[kTime] * scale_[kTime].factor + time_offset_;
  double step = kNaN;
  if (step_column_ >= 0 && step_column_ < static_cast<int>(cells_.size()))
    ParseCell(cells_[step_column_], layout_.decimal, &step);
  // A time of day without its date passing midnight: the next day.
  if (std::isfinite(t) && t <= previous_time_ && clock_.field >= 0 &&
      !clock_.dated && previous_time_ - t > 43200.0) {
    time_offset_ += 86400.0;
    t += 86400.0;
  }
  if (std::isfinite(t) && t <= previous_time_) {
    const bool step_changed = (step_column_ >= 0 && step != previous_step_ &&
                               !std::isnan(previous_step_)) ||
                              block_restart_;
    if (!step_changed) {
      return fmt::format(
          "{}: line {}: time {} {} is not after the previous {} {}; "
          "expected strictly increasing time",
          name_,
          line_no,
          value[kTime],
          scale_[kTime].unit,
          (previous_time_ - time_offset_) / scale_[kTime].factor,
          scale_[kTime].unit);
    }
    time_offset_ += previous_time_ - t + (last_dt_ > 0 ? last_dt_ : 0.0);
    t = value[kTime] * scale_[kTime].factor + time_offset_;
    ++meta_->clock_restarts_joined;
  }
  block_restart_ = false;
  if (std::isfinite(t)) {
    if (std::isfinite(previous_time_)) last_dt_ = t - previous_time_;
    previous_time_ = t;
  }
  value[kTime] = t;
  if (step_column_ >= 0 && step_column_ < static_cast<int>(cells_.size()))
    ParseCell(cells_[step_column_], layout_.decimal, &previous_step_);
  return {};
}

// Bad rows followed by a good one: an error, or dropped when lenient.
void RowReader::DropPending() {
  if (!options_.lenient) throw ForceError(pending_error_);
  dropped_ += pending_bad_rows_;
  if (meta_->warnings.empty() || dropped_ == pending_bad_rows_)
    meta_->warnings.push_back("first dropped row: " + pending_error_);
  pending_error_.clear();
  pending_bad_rows_ = 0;
  footer_rows_ = 0;
}

// One accepted row: time already on the joined clock, the other channels
// converted to N and mm here; runs of missing values are bounded.
void RowReader::Store(const double* values, long line_no) {
  for (int ch = 0; ch < kChannels; ++ch) {
    if (column_[ch] < 0) continue;
    const double x = ch == kTime ? values[ch] : values[ch] * scale_[ch].factor;
    // (A depth channel may be logged more sparsely: its gaps are counted
    // after the read.)
    if (std::isnan(x) && ch != kDepth) {
      if (++nan_run_[ch] > options_.max_nan_run) {
        throw ForceError(fmt::format(
            "{}: line {}: more than {} consecutive missing values in '{}'; "
            "expected isolated gaps at most",
            name_,
            line_no,
            options_.max_nan_run,
            layout_.names[column_[ch]]));
      }
    } else {
      nan_run_[ch] = 0;
    }
    Eigen::VectorXd& v = data_[ch];
    if (rows_stored_ >= v.size()) {
      prefault_.Stop();
      v.conservativeResize(2 * v.size() + 16);
    }
    v[rows_stored_] = x;
  }
  ++total_rows_;
  ++rows_stored_;
}

}  // namespace wearscar::force::internal
