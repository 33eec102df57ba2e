#include "split_read.h"

#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <thread>

#include "fields.h"

namespace wearscar::force::internal {

RowReader::Room RowReader::Reserved() {
  Room r;
  r.capacity = std::numeric_limits<Eigen::Index>::max();
  for (int ch = 0; ch < kChannels; ++ch) {
    if (column_[ch] < 0) continue;
    r.column[ch] = data_[ch].data();
    r.capacity = std::min(r.capacity, data_[ch].size());
  }
  return r;
}

RowReader::FastRows RowReader::ParseFastRows(FileLines& source,
                                             Eigen::Index at,
                                             const Room& room) {
  FastRows f;
  const bool timed = column_[kTime] >= 0;
  double previous = -std::numeric_limits<double>::infinity();
  int run[kChannels] = {};
  bool finite[kChannels] = {};
  std::string_view row;
  for (;;) {
    f.next_offset = source.Offset();
    if (!fast_possible_ || at + f.rows >= room.capacity || !source.Next(&row))
      break;
    double v[kChannels + 2];
    std::fill(std::begin(v), std::end(v), support::kNaN);
    if (!FastRow(
            row, layout_.delimiter, layout_.decimal, slot_of_field_, clock_, v))
      break;
    // TryFast's time with no clock joined (AdoptFastRows checks that).
    const double t = timed ? v[kTime] * scale_[kTime].factor + 0.0 : 0;
    if (timed && std::isfinite(t) && t <= previous) break;
    double x[kChannels];
    std::fill(std::begin(x), std::end(x), support::kNaN);
    bool too_long = false;
    for (int ch = 0; ch < kChannels; ++ch) {
      if (column_[ch] < 0) continue;
      x[ch] = ch == kTime ? t : v[ch] * scale_[ch].factor;
      too_long |= std::isnan(x[ch]) && run[ch] + 1 > options_.max_nan_run;
    }
    if (too_long) break;
    for (int ch = 0; ch < kChannels; ++ch) {
      if (column_[ch] < 0) continue;
      if (std::isnan(x[ch])) {
        ++run[ch];
        if (!finite[ch]) ++f.leading_nan[ch];
      } else {
        run[ch] = 0;
        finite[ch] = true;
      }
      room.column[ch][at + f.rows] = x[ch];
    }
    if (timed && std::isfinite(t)) {
      if (std::isfinite(previous)) {
        f.last_dt = t - previous;
      } else {
        f.first_time = t;
      }
      previous = t;
      f.last_time = t;
    }
    if (step_column_ >= 0) f.last_step = v[kStepSlot];
    ++f.rows;
  }
  for (int ch = 0; ch < kChannels; ++ch) f.trailing_nan[ch] = run[ch];
  return f;
}

bool RowReader::AdoptFastRows(const FastRows& f, Eigen::Index at) {
  if (f.rows == 0 || pending_bad_rows_ > 0 || time_offset_ != 0.0 ||
      rows_stored_ > at)
    return false;
  const bool timed = column_[kTime] >= 0;
  if (timed && std::isfinite(f.first_time) && f.first_time <= previous_time_)
    return false;
  for (int ch = 0; ch < kChannels; ++ch) {
    if (column_[ch] >= 0 && ch != kDepth &&
        nan_run_[ch] + f.leading_nan[ch] > options_.max_nan_run)
      return false;
  }
  for (int ch = 0; ch < kChannels; ++ch) {
    if (column_[ch] < 0) continue;
    double* v = data_[ch].data();
    if (at != rows_stored_) {
      std::memmove(v + rows_stored_,
                   v + at,
                   sizeof(double) * static_cast<std::size_t>(f.rows));
    }
    nan_run_[ch] = f.leading_nan[ch] == f.rows
                       ? nan_run_[ch] + static_cast<int>(f.rows)
                       : f.trailing_nan[ch];
  }
  if (timed && std::isfinite(f.first_time)) {
    if (std::isfinite(f.last_dt)) {
      last_dt_ = f.last_dt;
    } else if (std::isfinite(previous_time_)) {
      last_dt_ = f.first_time - previous_time_;
    }
    previous_time_ = f.last_time;
  }
  if (step_column_ >= 0) previous_step_ = f.last_step;
  rows_stored_ += f.rows;
  total_rows_ += static_cast<int>(f.rows);
  meta_->rows_on_second_thread += static_cast<long>(f.rows);
  return true;
}

long ReadRowsOnTwoThreads(RowReader& rows,
                          FileLines& lines,
                          long line_no,
                          int first_data_line,
                          const std::string& path,
                          std::uintmax_t file_bytes,
                          const ReadForceOptions& options) {
  const auto middle = static_cast<std::uintmax_t>(
      static_cast<double>(file_bytes) * options.split_share);
  const long head_lines = line_no;
  const RowReader::Room room = rows.Reserved();
  RowReader::FastRows second;
  LineStart start;
  bool second_ok = false;
  // The second thread finds its first line by counting the lines before
  // it, then parses from there while this one reads the lines before.
  std::thread thread([&] {
    try {
      std::unique_ptr<std::FILE, FileCloser> file(
          std::fopen(path.c_str(), "rb"));
      if (!file) return;
      start = FirstLineAfter(file.get(), middle);
      if (start.offset < 0 || start.lines_before <= head_lines) return;
      FileLines own(file.get(), path, options.max_line_bytes);
      own.SeekTo(static_cast<std::uintmax_t>(start.offset), start.lines_before);
      second =
          rows.ParseFastRows(own, start.lines_before - first_data_line, room);
      second_ok = true;
    } catch (const std::exception&) {
      // The careful pass meets whatever stopped it, and says so.
    }
  });
  struct Joiner {
    std::thread& t;
    ~Joiner() {
      if (t.joinable()) t.join();
    }
  } joiner{thread};
  std::string_view line;
  while (lines.Offset() <= middle && lines.Next(&line))
    rows.Handle(line, ++line_no);
  thread.join();
  if (second_ok && line_no == start.lines_before &&
      lines.Offset() == static_cast<std::uintmax_t>(start.offset) &&
      rows.AdoptFastRows(second, start.lines_before - first_data_line)) {
    line_no += static_cast<long>(second.rows);
    lines.SeekTo(second.next_offset, line_no);
  }
  return line_no;
}

}  // namespace wearscar::force::internal
