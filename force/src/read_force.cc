// The force reader's entry points: a file or text to a ForceRecord. The
// work is done by the pieces beside it, each one concern: encoding.h (what
// the first bytes are), line_source.h (lines), layout_detection.h (the
// layout of the head), columns.h (which column is which channel),
// fields.h and clock.h (cells and numbers), row_reader.h (the rows),
// split_read.h (a large file's rows on two threads), plausibility.h
// (units and limits).

#include "wearscar/force/read_force.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>

#include "appended_rows.h"
#include "columns.h"
#include "encoding.h"
#include "fields.h"
#include "layout_detection.h"
#include "line_source.h"
#include "plausibility.h"
#include "row_reader.h"
#include "split_read.h"
#include "units.h"
#include "wearscar/support/compressed.h"
#include "wearscar/support/text.h"

namespace wearscar::force {
namespace {

using internal::Channel;
using internal::CheckPlausible;
using internal::ChooseColumns;
using internal::Clock;
using internal::Columns;
using internal::CountLines;
using internal::DetectLayout;
using internal::EndsLinesWithCrAlone;
using internal::FileCloser;
using internal::FileLines;
using internal::FindClock;
using internal::FindStepColumn;
using internal::ForceToN;
using internal::InferUnits;
using internal::kChannels;
using internal::kDepth;
using internal::kP;
using internal::kQ;
using internal::kTime;
using internal::kWholeTextMaxBytes;
using internal::kX;
using internal::Layout;
using internal::LengthToMm;
using internal::LineSource;
using internal::MemoryLines;
using internal::RefuseWorkbook;
using internal::RequireChannels;
using internal::RequireNumbers;
using internal::ResolveUnit;
using internal::RowReader;
using internal::RowRoom;
using internal::Scale;
using internal::TimeToS;
using internal::TrimView;
using internal::Utf16Encoding;
using internal::Utf16ToUtf8;

// The first head_lines lines (copied: the source's views do not outlive a
// refill), without a UTF-8 byte-order mark; `more` says whether the file
// goes on. Throws for an empty file.
std::vector<std::string> ReadHead(LineSource& source,
                                  const std::string& name,
                                  int head_lines,
                                  bool* more) {
  std::vector<std::string> head;
  std::string_view line;
  *more = true;
  while (static_cast<int>(head.size()) < head_lines &&
         (*more = source.Next(&line))) {
    head.emplace_back(line);
  }
  if (!head.empty() && head[0].rfind("\xEF\xBB\xBF", 0) == 0)
    head[0].erase(0, 3);
  while (!head.empty() && TrimView(head.back()).empty() && !*more)
    head.pop_back();
  if (head.empty()) {
    throw ForceError(
        fmt::format("{}: the file is empty; expected a delimited "
                    "force export (header row, then numbers)",
                    name));
  }
  return head;
}

// Room for the rows: exact when the caller counted the lines; else, for a
// file of known size, as many rows as its shortest data line in the head
// allows (untouched memory costs nothing; the columns are trimmed in
// place), grown should that fall short. Mapped ahead: only the rows its
// longest data line allows, never pages the file will not fill.
RowRoom RowCapacity(const std::vector<std::string>& head,
                    const Layout& layout,
                    std::size_t lines,
                    std::uintmax_t file_bytes) {
  if (lines > 0 || file_bytes == 0) {
    const auto n = static_cast<Eigen::Index>(std::max<std::size_t>(lines, 16));
    return {n, n};
  }
  // (Blank lines are no measure of a row; none is shorter than "1,2".)
  constexpr std::size_t kShortestRow = 4;
  std::size_t head_bytes = 0, shortest = 0, longest = 0, data_lines = 0;
  for (std::size_t i = 0; i < head.size(); ++i) {
    const std::size_t bytes = head[i].size() + 1;  // its line break at least
    head_bytes += bytes;
    if (static_cast<int>(i) < layout.first_data_line) continue;
    ++data_lines;
    if (TrimView(head[i]).empty()) continue;
    shortest = shortest == 0 ? bytes : std::min(shortest, bytes);
    longest = std::max(longest, bytes);
  }
  const std::uintmax_t rest =
      file_bytes > head_bytes ? file_bytes - head_bytes : 0;
  // (CRLF lines are a byte longer than counted: fewer still.)
  return {static_cast<Eigen::Index>(
              data_lines + rest / std::max(shortest, kShortestRow) + 16),
          static_cast<Eigen::Index>(
              longest > 0 ? data_lines + rest / (longest + 1) : 0)};
}

// The time axis: the file's, or rebuilt from the rate in its metadata or
// the options.
void SetTime(ForceRecord* record,
             Eigen::VectorXd* time,
             const Layout& layout,
             const ReadForceOptions& options,
             const std::string& name) {
  ForceMetadata& meta = record->metadata;
  if (time->size() > 0) {
    record->time_s = std::move(*time);
    if (record->size() > 1) {
      const double span =
          record->time_s[record->size() - 1] - record->time_s[0];
      if (span > 0) meta.sampling_rate_hz = (record->size() - 1) / span;
    }
    return;
  }
  const double rate = layout.metadata_rate_hz > 0 ? layout.metadata_rate_hz
                                                  : options.sampling_rate_hz;
  if (!(rate > 0)) {
    throw ForceError(fmt::format(
        "{}: no time column and no sampling rate in the metadata; expected a "
        "'Time' column or a line such as 'Sampling frequency [Hz]: 100' "
        "(or give the rate explicitly)",
        name));
  }
  meta.sampling_rate_hz = rate;
  meta.time_rebuilt = true;
  record->time_s = Eigen::VectorXd::LinSpaced(
      record->x_mm.size(), 0.0, (record->x_mm.size() - 1) / rate);
}

// Compression positive, whatever the instrument's sign (the median of up to
// 4096 samples decides).
void MakeCompressionPositive(ForceRecord* record) {
  std::vector<double> finite;
  const Eigen::Index n = record->size();
  for (Eigen::Index i = 0; i < n; i += std::max<Eigen::Index>(1, n / 4096)) {
    if (std::isfinite(record->normal_n[i]))
      finite.push_back(record->normal_n[i]);
  }
  if (finite.empty()) return;
  std::nth_element(
      finite.begin(), finite.begin() + finite.size() / 2, finite.end());
  if (finite[finite.size() / 2] < 0) {
    record->normal_n = -record->normal_n;
    record->metadata.normal_sign_flipped = true;
  }
}

// The checks of a whole record, from one pass over its samples: values no
// tribometer measured, no friction recorded, channels in each other's
// roles; P made positive in compression.
void CheckRecord(const ReadForceOptions& options,
                 const std::string& name,
                 ForceRecord* record) {
  const internal::SampleCensus census = internal::TakeCensus(*record);
  CheckPlausible(*record, census, name);
  internal::CheckFrictionRecorded(*record, census, name);
  MakeCompressionPositive(record);
  if (!options.channels_as_given)
    internal::CheckChannelRoles(*record, census, name);
}

}  // namespace

namespace internal {
// Everything of the head that the rows are read with.
struct ReadPlan {
  std::vector<std::string> head;
  bool more = true;  // lines after the head
  Layout layout;
  Columns column;
  Clock clock;
  Scale scale[kChannels];
};
}  // namespace internal

namespace {

using internal::ReadPlan;

// What the head says: the layout, the columns, the clock, the units. With
// `known` (rows appended to a file whose head was planned), its plan on
// this head's lines.
ReadPlan PlanRead(LineSource& source,
                  const std::string& name,
                  const ReadForceOptions& options,
                  ForceMetadata* meta,
                  const ReadPlan* known = nullptr) {
  ReadPlan p;
  if (known != nullptr) {
    p.layout = known->layout;
    p.column = known->column;
    p.clock = known->clock;
    std::copy(
        std::begin(known->scale), std::end(known->scale), std::begin(p.scale));
    // The header's lines alone: the rows are read as they come.
    p.head =
        ReadHead(source, name, std::max(1, p.layout.first_data_line), &p.more);
    meta->source = name;
    meta->layout = p.layout.kind->name;
    meta->stated = p.layout.stated;
    return p;
  }
  p.head = ReadHead(source, name, options.head_lines, &p.more);
  p.layout = DetectLayout(p.head, name, options);
  p.column = ChooseColumns(p.layout, options, name);
  RequireChannels(p.column, p.layout, name);
  p.clock = FindClock(p.head, p.column, p.layout);
  // A depth column found by its name but holding text is no depth channel.
  if (p.column[kDepth] >= 0 && options.depth_column.empty()) {
    try {
      RequireNumbers(p.head, p.column, p.layout, p.clock, name);
    } catch (const ForceError&) {
      p.column[kDepth] = -1;
    }
  }
  RequireNumbers(p.head, p.column, p.layout, p.clock, name);
  const std::string& p_name = p.layout.names[p.column[kP]];
  if (support::Lower(p_name).find("nominal") != std::string::npos) {
    meta->warnings.push_back(fmt::format(
        "P is the column '{}': the load set on the instrument, not a "
        "measured force; used as P (a dead weight presses with its weight)",
        p_name));
  }
  meta->source = name;
  meta->layout = p.layout.kind->name;
  meta->stated = p.layout.stated;
  for (int ch = 0; ch < kChannels; ++ch) {
    if (p.column[ch] < 0) continue;
    p.scale[ch] = ch == kTime && p.clock.field >= 0
                      ? Scale{1.0, "s", false, {}}  // a clock's seconds
                      : ResolveUnit(Channel(ch),
                                    p.layout.units[p.column[ch]],
                                    options,
                                    name,
                                    p.layout.names[p.column[ch]],
                                    *p.layout.kind,
                                    &meta->warnings);
  }
  return p;
}

// The depth channel into the record, penetration positive (a height: Z, a
// position, is turned over); a column empty on more than 1% of the rows is
// not used, with a warning.
void TakeDepth(const std::string& column,
               Eigen::VectorXd* depth,
               ForceRecord* record) {
  ForceMetadata& meta = record->metadata;
  long missing = 0;
  for (Eigen::Index i = 0; i < depth->size(); ++i)
    missing += !std::isfinite((*depth)[i]);
  if (missing > 0.01 * static_cast<double>(depth->size())) {
    meta.warnings.push_back(fmt::format(
        "the depth column '{}' is empty on {:.0f}% of the rows: not used",
        column,
        100.0 * missing / std::max<Eigen::Index>(1, depth->size())));
    return;
  }
  meta.depth_is_penetration = internal::NamesAPenetration(column);
  record->depth_mm =
      meta.depth_is_penetration ? std::move(*depth) : Eigen::VectorXd(-*depth);
}

// `lines`: the file's line count when the caller counted them (0: not);
// `file_bytes` its size when known; `split`: `source` itself, to be read
// on two threads (ReadRowsOnTwoThreads).
// Rows appended to a record read before (ReadAppendedRows): `first`, that
// record's (the checks of a whole record are its, and P's sign follows
// its); `plan`, the head's plan when kept from the last rows appended, or
// where to keep it.
struct Continues {
  const ForceMetadata* first = nullptr;
  internal::KeptPlan* plan = nullptr;
};

// `continues`: the record these rows continue (ReadAppendedRows).
ForceRecord Read(LineSource& source,
                 const std::string& name,
                 std::size_t lines,
                 const ReadForceOptions& options,
                 std::uintmax_t file_bytes = 0,
                 FileLines* split = nullptr,
                 Continues continues = {}) {
  std::string why;
  if (!options.IsValid(&why))
    throw ForceError(fmt::format("{}: invalid read options: {}", name, why));
  ForceRecord record;
  ForceMetadata& meta = record.metadata;
  internal::KeptPlan* kept = continues.plan;
  const ReadPlan p = PlanRead(
      source, name, options, &meta, kept != nullptr ? kept->get() : nullptr);
  if (kept != nullptr && !*kept) {
    *kept = std::make_shared<ReadPlan>(p);
    (*kept)->head.clear();
  }
  const Layout& layout = p.layout;
  meta.first_data_line = layout.first_data_line;
  RowReader rows(
      layout,
      layout.header_line >= 0 ? &p.head[layout.header_line] : nullptr,
      p.column,
      FindStepColumn(layout),
      p.clock,
      p.scale,
      options,
      name,
      RowCapacity(p.head, layout, lines, file_bytes),
      &meta);
  long line_no = 0;
  for (const auto& h : p.head) {
    ++line_no;
    if (line_no - 1 >= layout.first_data_line) rows.Handle(h, line_no);
  }
  std::string_view line;
  if (p.more && split != nullptr) {
    line_no = internal::ReadRowsOnTwoThreads(rows,
                                             *split,
                                             line_no,
                                             layout.first_data_line,
                                             name,
                                             file_bytes,
                                             options);
  }
  if (p.more) {
    while (source.Next(&line)) rows.Handle(line, ++line_no);
  }
  std::array<Eigen::VectorXd, kChannels> data = rows.Finish();
  Scale scale[kChannels];
  std::copy(std::begin(p.scale), std::end(p.scale), std::begin(scale));
  InferUnits(data.data(), scale, p.column, layout, name, &meta);
  for (int ch = 0; ch < kChannels; ++ch) {
    const bool read = p.column[ch] >= 0;
    if (ch == kDepth && !read) break;  // the depth's entries only with one
    meta.channel_names.push_back(read ? layout.names[p.column[ch]] : "");
    meta.channel_units.push_back(read ? scale[ch].unit : "");
  }
  record.x_mm = std::move(data[kX]);
  record.tangential_n = std::move(data[kQ]);
  record.normal_n = std::move(data[kP]);
  if (p.column[kDepth] >= 0)
    TakeDepth(layout.names[p.column[kDepth]], &data[kDepth], &record);
  SetTime(&record, &data[kTime], layout, options, name);
  if (continues.first != nullptr) {
    if (continues.first->normal_sign_flipped) {
      record.normal_n = -record.normal_n;
      meta.normal_sign_flipped = true;
    }
    return record;
  }
  CheckRecord(options, name, &record);
  return record;
}

// A FIFO would block on open, /dev/zero never end: regular files only.
void RequireRegularFile(const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || std::filesystem::is_regular_file(status)) return;
  using std::filesystem::file_type;
  const file_type type = status.type();
  throw ForceError(
      fmt::format("{}: not a regular file ({}); expected a force export",
                  path,
                  type == file_type::directory   ? "a directory"
                  : type == file_type::fifo      ? "a FIFO"
                  : type == file_type::character ? "a character device"
                  : type == file_type::block     ? "a block device"
                  : type == file_type::socket    ? "a socket"
                  : type == file_type::not_found ? "not found"
                                                 : "not a file"));
}

// A file read whole as text (UTF-16 converted; CR line ends), its bytes
// handed on as they are read.
std::string ReadWholeText(std::FILE* f,
                          const std::string& path,
                          const char* encoding,
                          std::uintmax_t size_hint,
                          const ReadForceOptions& options) {
  const auto read = [&](char* into, std::size_t room) {
    const std::size_t n = std::fread(into, 1, room, f);
    if (n == 0 && std::ferror(f)) {
      throw ForceError(
          fmt::format("{}: read error: {}", path, std::strerror(errno)));
    }
    return n;
  };
  if (encoding != nullptr)
    return Utf16ToUtf8(read, encoding, path, size_hint, options.on_bytes);
  std::string text;
  std::vector<char> block(std::size_t{1} << 20);
  while (const std::size_t got = read(block.data(), block.size())) {
    if (options.on_bytes) options.on_bytes(block.data(), got);
    text.append(block.data(), got);
    if (text.size() > kWholeTextMaxBytes) {
      throw ForceError(fmt::format(
          "{}: more than {} MiB of text with lines ended by CR alone; "
          "expected at most that (convert the line ends to LF first)",
          path,
          kWholeTextMaxBytes >> 20));
    }
  }
  return text;
}

// A gzip or zstd file: read whole, expanded in memory, then as text.
ForceRecord ReadCompressed(std::FILE* f,
                           const std::string& path,
                           support::Compression packed,
                           const ReadForceOptions& options) {
  std::string bytes;
  std::vector<char> block(std::size_t{1} << 20);
  while (const std::size_t got = std::fread(block.data(), 1, block.size(), f)) {
    if (options.on_bytes) options.on_bytes(block.data(), got);
    bytes.append(block.data(), got);
    if (bytes.size() > internal::kCompressedMaxBytes) break;
  }
  if (std::ferror(f)) {
    throw ForceError(
        fmt::format("{}: read error: {}", path, std::strerror(errno)));
  }
  std::string text, why;
  if (!support::Decompress(
          bytes, packed, internal::kCompressedMaxBytes, false, &text, &why)) {
    throw ForceError(fmt::format(
        "{}: {}-compressed: {}{}",
        path,
        support::CompressionName(packed),
        why,
        why.find("MiB") != std::string::npos ? " (decompress it first)" : ""));
  }
  ReadForceOptions text_options = options;
  text_options.on_bytes = nullptr;  // handed on as they were read
  return ReadForceText(text, path, text_options);
}

}  // namespace

bool ReadForceOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (sampling_rate_hz < 0) return fail("sampling_rate_hz must be >= 0");
  if (!(max_dropped_fraction >= 0 && max_dropped_fraction <= 1))
    return fail("max_dropped_fraction must be in [0, 1]");
  if (max_nan_run < 0) return fail("max_nan_run must be >= 0");
  if (max_line_bytes < 64) return fail("max_line_bytes must be >= 64");
  if (head_lines < 2 || head_lines > 100000)
    return fail("head_lines must be 2 to 100000");
  if (delimiter_vote_lines < 1)
    return fail("delimiter_vote_lines must be >= 1");
  if (threads < 1 || threads > 2) return fail("threads must be 1 or 2");
  if (!(split_share >= 0.05 && split_share <= 0.95))
    return fail("split_share must be in [0.05, 0.95]");
  if (!x_unit.empty() && !LengthToMm(x_unit))
    return fail("the x unit is not a length unit (mm, um, m, ...)");
  if (!force_unit.empty() && !ForceToN(force_unit))
    return fail("the force unit is not a force unit (N, mN, kN, gf, ...)");
  if (!time_unit.empty() && !TimeToS(time_unit))
    return fail("the time unit is not a time unit (s, ms, min, ...)");
  return true;
}

ForceRecord ReadForceFile(const std::string& path,
                          const ReadForceOptions& options) {
  RequireRegularFile(path);
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) {
    throw ForceError(
        fmt::format("{}: cannot open: {}", path, std::strerror(errno)));
  }
  std::error_code size_error;
  const std::uintmax_t size = std::filesystem::file_size(path, size_error);
  // What the first 64 KiB tell: gzip or zstd (expanded, then as text), a
  // workbook (refused), UTF-16 text or lines ended by CR alone (read whole,
  // then as text); else streamed.
  std::string first(std::size_t{64} << 10, '\0');
  first.resize(std::fread(first.data(), 1, first.size(), file.get()));
  std::rewind(file.get());
  const support::Compression packed = support::CompressionOf(first);
  if (packed != support::Compression::kNone)
    return ReadCompressed(file.get(), path, packed, options);
  RefuseWorkbook(first, path);
  const char* encoding = Utf16Encoding(first);
  if (encoding != nullptr || EndsLinesWithCrAlone(first)) {
    const std::string text =
        ReadWholeText(file.get(),
                      path,
                      encoding,
                      size_error ? std::uintmax_t{1} << 20 : size,
                      options);
    ReadForceOptions text_options = options;
    text_options.on_bytes = nullptr;  // handed on as they were read
    return ReadForceText(text, path, text_options);
  }
  // Up to kWholeTextMaxBytes in one pass, the columns sized from the
  // file's size (their room to spare, never written, costs little); larger
  // files are counted first, so that their columns are sized exactly.
  if (!size_error && size > 0 && size <= kWholeTextMaxBytes) {
    FileLines source(
        file.get(), path, options.max_line_bytes, options.on_bytes);
    const bool split = options.threads >= 2 && !options.on_bytes &&
                       size >= internal::kSplitMinBytes;
    return Read(source, path, 0, options, size, split ? &source : nullptr);
  }
  const std::size_t lines = CountLines(file.get(), options.on_bytes);
  FileLines source(file.get(), path, options.max_line_bytes);
  return Read(source, path, lines, options);
}

ForceRecord ReadForceText(const std::string& text,
                          const std::string& name,
                          const ReadForceOptions& options) {
  RefuseWorkbook(text, name);
  if (const char* encoding = Utf16Encoding(text)) {
    std::size_t at = 0;
    const auto read = [&](char* into, std::size_t room) {
      const std::size_t n = std::min(room, text.size() - at);
      std::memcpy(into, text.data() + at, n);
      at += n;
      return n;
    };
    // ReadForceText hands on no bytes.
    return ReadForceText(
        Utf16ToUtf8(read, encoding, name, text.size(), nullptr), name, options);
  }
  if (EndsLinesWithCrAlone(text)) {
    std::string lf = text;
    std::replace(lf.begin(), lf.end(), '\r', '\n');
    return ReadForceText(lf, name, options);
  }
  MemoryLines source(text, name, options.max_line_bytes);
  const std::size_t lines =
      internal::CountLineBreaks(text.data(), text.data() + text.size()) + 1;
  return Read(source, name, lines, options);
}

namespace internal {

ForceRecord ReadAppendedRows(const std::string& text,
                             const std::string& name,
                             const ReadForceOptions& options,
                             const ForceMetadata& first,
                             KeptPlan* plan) {
  ReadForceOptions pinned = options;
  pinned.on_bytes = nullptr;
  pinned.threads = 1;
  // The units the first rows were read in (time, x, Q, P, depth): Q and P
  // share one, P's.
  std::string* unit[] = {&pinned.time_unit,
                         &pinned.x_unit,
                         nullptr,
                         &pinned.force_unit,
                         &pinned.depth_unit};
  for (std::size_t ch = 0; ch < first.channel_units.size() && ch < 5; ++ch) {
    if (unit[ch] != nullptr && !first.channel_units[ch].empty())
      *unit[ch] = first.channel_units[ch];
  }
  MemoryLines source(text, name, options.max_line_bytes);
  const std::size_t lines =
      internal::CountLineBreaks(text.data(), text.data() + text.size()) + 1;
  return Read(source, name, lines, pinned, 0, nullptr, {&first, plan});
}

}  // namespace internal
}  // namespace wearscar::force
