#include "wearscar/force/follow.h"

#include <fmt/format.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "appended_rows.h"
#include "line_source.h"

namespace wearscar::force {
namespace {

// Rows read again before the appended ones.
constexpr int kOverlapRows = 8;

long CountLineBreaks(const std::string& text) {
  return static_cast<long>(
      internal::CountLineBreaks(text.data(), text.data() + text.size()));
}

// The last line of `text` with something on it, without its line break.
std::string LastLine(const std::string& text) {
  std::size_t end = text.size();
  while (end > 0) {
    while (end > 0 && (text[end - 1] == '\n' || text[end - 1] == '\r')) --end;
    const std::size_t begin = text.rfind('\n', end == 0 ? 0 : end - 1);
    const std::size_t from = begin == std::string::npos ? 0 : begin + 1;
    const std::string line = text.substr(from, end - from);
    if (line.find_first_not_of(" \t") != std::string::npos) return line;
    end = from;
  }
  return {};
}

// Adds to `lines` (last first, while it holds fewer than `k`) the lines of
// `text` with something on them, from its end, without their line breaks.
void AddLastLines(std::string_view text,
                  int k,
                  std::vector<std::string_view>* lines) {
  std::size_t end = text.size();
  while (end > 0 && static_cast<int>(lines->size()) < k) {
    while (end > 0 && (text[end - 1] == '\n' || text[end - 1] == '\r')) --end;
    if (end == 0) break;
    const std::size_t nl = text.rfind('\n', end - 1);
    const std::size_t from = nl == std::string_view::npos ? 0 : nl + 1;
    const std::string_view line = text.substr(from, end - from);
    if (line.find_first_not_of(" \t") != std::string_view::npos)
      lines->push_back(line);
    end = from;
  }
}

// The last `k` lines of `before` + `text` with something on them, each with
// its line break, and how many: read backwards from the end, so that a
// look's text is not copied (it was, once per line kept).
std::pair<std::string, int> LastLines(const std::string& before,
                                      const std::string& text,
                                      int k) {
  std::vector<std::string_view> lines;
  AddLastLines(text, k, &lines);
  AddLastLines(before, k, &lines);
  std::string out;
  for (auto it = lines.rbegin(); it != lines.rend(); ++it) {
    out.append(it->data(), it->size());
    out += '\n';
  }
  return {out, static_cast<int>(lines.size())};
}

// The first `lines` lines of `text`, each with its line break.
std::string FirstLines(const std::string& text, int lines) {
  std::size_t at = 0;
  for (int i = 0; i < lines && at < text.size(); ++i) {
    const std::size_t nl = text.find('\n', at);
    at = nl == std::string::npos ? text.size() : nl + 1;
  }
  return text.substr(0, at);
}

// The rows [from, size) of a record.
ForceRecord Tail(ForceRecord r, Eigen::Index from) {
  const Eigen::Index n = std::max<Eigen::Index>(0, r.size() - from);
  r.time_s = r.time_s.tail(n).eval();
  r.x_mm = r.x_mm.tail(n).eval();
  r.tangential_n = r.tangential_n.tail(n).eval();
  r.normal_n = r.normal_n.tail(n).eval();
  if (r.has_depth()) r.depth_mm = r.depth_mm.tail(n).eval();
  return r;
}

}  // namespace

ForceFollower::ForceFollower(std::string path, FollowOptions options)
    : path_(std::move(path)), options_(std::move(options)) {}

ForceFollower::~ForceFollower() = default;

void ForceFollower::Reset() {
  file_.reset();
  inode_ = device_ = 0;
  offset_ = read_ = 0;
  lines_ = 0;
  pending_.clear();
  head_.clear();
  started_ = false;
  first_ = ForceMetadata{};
  header_.clear();
  last_rows_.clear();
  last_row_count_ = 0;
  last_time_s_ = 0.0;
  plan_.reset();
}

// Opens the file when it is not open, and starts again when it was
// replaced or truncated. False when there is nothing to read yet.
bool ForceFollower::Reopen(FollowedRows* out) {
  struct stat st {};
  if (::stat(path_.c_str(), &st) != 0) {
    if (!file_ && !announced_missing_) {
      announced_missing_ = true;
      out->note = fmt::format("{}: not there yet ({}); waiting for it",
                              path_,
                              std::strerror(errno));
    }
    return static_cast<bool>(file_);  // moved away: its rows are read on
  }
  if (!S_ISREG(st.st_mode)) {
    throw ForceError(fmt::format(
        "{}: not a regular file; expected a force export being written",
        path_));
  }
  const auto inode = static_cast<std::uintmax_t>(st.st_ino);
  const auto device = static_cast<std::uintmax_t>(st.st_dev);
  const auto size = static_cast<std::uintmax_t>(st.st_size);
  if (file_ && (inode != inode_ || device != device_)) {
    const bool had = read_ > 0;
    Reset();
    if (had) {
      out->restarted = true;
      out->note = fmt::format(
          "{}: replaced by another file: a new test, read from its start",
          path_);
    }
  } else if (file_ && size < read_) {
    out->restarted = true;
    out->note = fmt::format(
        "{}: truncated ({} bytes, after {} read): a new test, read from its "
        "start",
        path_,
        size,
        read_);
    Reset();
  }
  if (!file_) {
    file_.reset(std::fopen(path_.c_str(), "rb"));
    if (!file_) {
      throw ForceError(
          fmt::format("{}: cannot open: {}", path_, std::strerror(errno)));
    }
    inode_ = inode;
    device_ = device;
  }
  return true;
}

std::string ForceFollower::TakeCompleteLines() {
  if (!block_) {
    block_size_ = std::min<std::size_t>(options_.max_bytes_per_poll,
                                        std::size_t{1} << 20);
    block_.reset(new char[block_size_]);
  }
  std::size_t taken = 0;
  std::clearerr(file_.get());
  if (std::fseek(file_.get(), static_cast<long>(read_), SEEK_SET) != 0) {
    throw ForceError(
        fmt::format("{}: cannot seek: {}", path_, std::strerror(errno)));
  }
  while (taken < options_.max_bytes_per_poll) {
    const std::size_t got =
        std::fread(block_.get(), 1, block_size_, file_.get());
    if (got == 0) break;
    pending_.append(block_.get(), got);
    taken += got;
    read_ += got;
  }
  const std::size_t end = pending_.rfind('\n');
  std::string text;
  if (end != std::string::npos) {
    // The lines leave without a copy; only the part line after them is.
    text = std::move(pending_);
    pending_.assign(text, end + 1, std::string::npos);
    text.resize(end + 1);
    offset_ += text.size();
  }
  if (pending_.size() > options_.read.max_line_bytes) {
    throw ForceError(fmt::format(
        "{}: no line break in {} bytes from byte {}; expected a text export "
        "of lines of at most {} bytes",
        path_,
        pending_.size(),
        offset_,
        options_.read.max_line_bytes));
  }
  return text;
}

void ForceFollower::ReadFirstRows(const std::string& text, FollowedRows* out) {
  if (text.find('\0') != std::string::npos) {
    throw ForceError(fmt::format(
        "{}: NUL bytes in its first lines (UTF-16 text?); expected UTF-8 or "
        "ASCII text to follow as it grows (wearscar fuse reads the finished "
        "file)",
        path_));
  }
  ForceRecord record = ReadForceText(text, path_, options_.read);
  first_ = record.metadata;
  header_ = FirstLines(text, first_.first_data_line);
  last_rows_ = LastLines({}, text, kOverlapRows).first;
  last_row_count_ = OverlapRows();
  if (record.size() > 0) last_time_s_ = record.time_s[record.size() - 1];
  started_ = true;
  out->rows = std::move(record);
}

void ForceFollower::ReadMoreRows(const std::string& text,
                                 long text_lines,
                                 FollowedRows* out) {
  if (LastLine(text).empty()) return;  // blank lines only
  const long from_line = lines_ - text_lines + 1;
  const std::string name = fmt::format(
      "{} (the rows appended from line {}; lines counted from the "
      "header's end)",
      path_,
      from_line);
  // The last rows read before go first: the layout is found again on
  // them, and the last one puts a clock that restarts, or one rebuilt from
  // the rate, on the rows' own.
  ForceRecord record = internal::ReadAppendedRows(
      header_ + last_rows_ + text, name, options_.read, first_, &plan_);
  const Eigen::Index old = last_row_count_;
  if (record.size() <= old) return;  // a footer
  const double shift = old > 0 ? last_time_s_ - record.time_s[old - 1] : 0.0;
  if (shift != 0.0) record.time_s.array() += shift;
  ForceRecord rows = Tail(std::move(record), old);
  rows.metadata = first_;
  last_rows_ = LastLines(last_rows_, text, kOverlapRows).first;
  last_row_count_ = OverlapRows();
  last_time_s_ = rows.time_s[rows.size() - 1];
  out->rows = std::move(rows);
}

// The data rows among the overlap's lines, as the reader reads them: a
// repeated block's header line (a CETR step, a block of --pattern) is a
// line but no row. Counting it made the next look drop its first row and
// shift its clock by a sample.
int ForceFollower::OverlapRows() const {
  // The kept plan, never one found on these few lines.
  std::shared_ptr<internal::ReadPlan> plan = plan_;
  try {
    return static_cast<int>(
        internal::ReadAppendedRows(
            header_ + last_rows_, path_, options_.read, first_, &plan)
            .size());
  } catch (const ForceError&) {
    return 0;  // header lines alone
  }
}

FollowedRows ForceFollower::Poll(bool idle) {
  FollowedRows out;
  if (!Reopen(&out)) return out;
  const std::string text = TakeCompleteLines();
  const long text_lines = static_cast<long>(CountLineBreaks(text));
  lines_ += text_lines;
  if (started_) {
    ReadMoreRows(text, text_lines, &out);
    return out;
  }
  head_ += text;
  const long head_lines = CountLineBreaks(head_);
  const bool enough = head_lines >= options_.first_lines ||
                      (idle && head_lines >= 20 && !LastLine(head_).empty());
  if (!enough) return out;
  try {
    ReadFirstRows(head_, &out);
  } catch (const ForceError&) {
    if (head_lines >= options_.first_lines) throw;
    return out;  // a short start: more lines may make it readable
  }
  head_.clear();
  if (out.note.empty()) {
    out.note = fmt::format(
        "{}: {} layout, units time {}, x {}, forces {}",
        path_,
        first_.layout,
        first_.channel_units.size() > 0 ? first_.channel_units[0] : "?",
        first_.channel_units.size() > 1 ? first_.channel_units[1] : "?",
        first_.channel_units.size() > 3 ? first_.channel_units[3] : "?");
  }
  return out;
}

}  // namespace wearscar::force
