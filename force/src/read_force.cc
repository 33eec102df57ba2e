#include "wearscar/force/read_force.h"

#include <fast_float/fast_float.h>
#include <fmt/format.h>
#include <iconv.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string_view>
#include <thread>
#include <vector>

#include "layouts.h"
#include "units.h"
#include "wearscar/support/check.h"
#include "wearscar/support/huge_pages.h"
#include "wearscar/support/text.h"

namespace wearscar::force {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------------------
// Line sources: the reader streams the file in blocks so that the text is
// never held whole next to the numbers (memory stays near the numeric data).

class LineSource {
 public:
  virtual ~LineSource() = default;
  // Next line without its terminator ("\n" or "\r\n"); false at the end.
  virtual bool Next(std::string_view* line) = 0;
};

class MemoryLines : public LineSource {
 public:
  MemoryLines(std::string_view text, std::string name, size_t max_line)
      : text_(text), name_(std::move(name)), max_line_(max_line) {}
  bool Next(std::string_view* line) override {
    if (pos_ >= text_.size()) return false;
    size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) end = text_.size();
    ++lines_;
    if (end - pos_ > max_line_) {
      throw ForceError(fmt::format(
          "{}: line {}: more than {} bytes without a line break; expected a "
          "delimited text export",
          name_,
          lines_,
          max_line_));
    }
    *line = text_.substr(pos_, end - pos_);
    if (!line->empty() && line->back() == '\r') line->remove_suffix(1);
    pos_ = end + 1;
    return true;
  }

 private:
  std::string_view text_;
  std::string name_;
  size_t max_line_;
  size_t pos_ = 0;
  long lines_ = 0;
};

class FileLines : public LineSource {
 public:
  // `on_bytes`, when given, is handed every byte read, in order (a reader
  // that never seeks hands it the whole file).
  FileLines(std::FILE* file,
            std::string name,
            size_t max_line,
            std::function<void(const char*, std::size_t)> on_bytes = {})
      : file_(file),
        name_(std::move(name)),
        max_line_(max_line),
        on_bytes_(std::move(on_bytes)),
        buffer_(std::min(kBlock, std::max<size_t>(max_line, 1024))) {}
  bool Next(std::string_view* line) override {
    for (;;) {
      const char* begin = buffer_.data() + pos_;
      const char* nl =
          static_cast<const char*>(std::memchr(begin, '\n', filled_ - pos_));
      if (nl != nullptr) {
        *line = std::string_view(begin, static_cast<size_t>(nl - begin));
        pos_ = static_cast<size_t>(nl - buffer_.data()) + 1;
        ++lines_;
        if (!line->empty() && line->back() == '\r') line->remove_suffix(1);
        return true;
      }
      if (eof_) {
        if (pos_ >= filled_) return false;
        *line = std::string_view(begin, filled_ - pos_);
        pos_ = filled_;
        ++lines_;
        if (!line->empty() && line->back() == '\r') line->remove_suffix(1);
        return true;
      }
      Refill();
    }
  }

  // The file offset of the next line.
  long Offset() const { return base_ + static_cast<long>(pos_); }

  // Continues at `offset`, the start of line `lines` + 1.
  void SeekTo(long offset, long lines) {
    if (std::fseek(file_, offset, SEEK_SET) != 0) {
      throw ForceError(
          fmt::format("{}: seek error: {}", name_, std::strerror(errno)));
    }
    base_ = offset;
    pos_ = filled_ = 0;
    eof_ = false;
    lines_ = lines;
  }

 private:
  static constexpr size_t kBlock = size_t{1} << 20;
  void Refill() {
    // Move the partial line to the front; grow only for a long line, up to
    // kMaxLineBytes (a text export's lines are short; one without breaks
    // is not a text export).
    std::memmove(buffer_.data(), buffer_.data() + pos_, filled_ - pos_);
    base_ += static_cast<long>(pos_);
    filled_ -= pos_;
    pos_ = 0;
    if (filled_ == buffer_.size()) {
      if (buffer_.size() >= max_line_) {
        throw ForceError(fmt::format(
            "{}: line {}: more than {} bytes without a line break; expected "
            "a delimited text export",
            name_,
            lines_ + 1,
            max_line_));
      }
      buffer_.resize(buffer_.size() * 2);
    }
    const size_t got = std::fread(
        buffer_.data() + filled_, 1, buffer_.size() - filled_, file_);
    if (got > 0 && on_bytes_) on_bytes_(buffer_.data() + filled_, got);
    if (got == 0) {
      if (std::ferror(file_)) {
        throw ForceError(
            fmt::format("{}: read error: {}", name_, std::strerror(errno)));
      }
      eof_ = true;
    }
    filled_ += got;
  }
  std::FILE* file_;
  std::string name_;
  size_t max_line_;
  std::function<void(const char*, std::size_t)> on_bytes_;
  std::vector<char> buffer_;
  long base_ = 0;  // the file offset of buffer_[0]
  size_t pos_ = 0, filled_ = 0;
  long lines_ = 0;
  bool eof_ = false;
};

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

// Where a second thread parses the rows of a file from: the first line
// that starts after byte `middle`, at `offset` after `lines_before` lines
// (CountLines), or, with offset -1, found by the second thread itself.
struct SplitPoint {
  std::string path;
  long middle = 0;
  long offset = -1;
  long lines_before = 0;
  FileLines* lines = nullptr;  // the first thread's, which then seeks past
};

// Files smaller than this are parsed on one thread.
constexpr long kSplitMinBytes = long{2} << 20;
// Files up to this size are read in one pass, not counted first
// (ReadForceFile).
constexpr long kEstimateMaxBytes = long{256} << 20;

// ---------------------------------------------------------------------------
// Cells.

std::string_view TrimView(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) {
    s.remove_prefix(1);
  }
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) {
    s.remove_suffix(1);
  }
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') {
    s = s.substr(1, s.size() - 2);
  }
  return s;
}

using support::Lower;

// Splits `line` on `delim` into `cells` (views into line), cells trimmed,
// by RFC 4180: a cell in double quotes may hold the delimiter ("Time, s");
// its view keeps a doubled quote as two characters.
void Split(std::string_view line,
           char delim,
           std::vector<std::string_view>* cells) {
  cells->clear();
  size_t start = 0;
  for (;;) {
    size_t scan = start;
    while (scan < line.size() && (line[scan] == ' ' || line[scan] == '\t') &&
           line[scan] != delim)
      ++scan;
    if (scan < line.size() && line[scan] == '"') {
      // Quoted: up to the closing quote (a doubled quote is an escape).
      size_t q = scan + 1;
      while (q < line.size()) {
        if (line[q] == '"') {
          if (q + 1 < line.size() && line[q + 1] == '"') {
            q += 2;
            continue;
          }
          break;
        }
        ++q;
      }
      scan = q < line.size() ? q + 1 : q;
    }
    const size_t end = line.find(delim, scan);
    if (end == std::string_view::npos) {
      cells->push_back(TrimView(line.substr(start)));
      break;
    }
    cells->push_back(TrimView(line.substr(start, end - start)));
    start = end + 1;
  }
}

// Cells of a row without the empty cell a trailing delimiter adds (Rtec ends
// every row with one).
size_t CountWithoutTrailing(const std::vector<std::string_view>& cells) {
  return cells.size() > 1 && cells.back().empty() ? cells.size() - 1
                                                  : cells.size();
}

// The markers spreadsheets and programs write for a missing value: Excel's
// "#N/A" ("#NV" in German), R's "NA", "N/A", "null", and the NaN of
// Microsoft's C library ("-nan(ind)", and "1.#QNAN", "-1.#IND" of older
// ones) in a home-built rig's log (any case).
bool IsMissingMarker(std::string_view cell) {
  if (cell.size() < 2 || cell.size() > 9) return false;
  if (cell[0] == '-' || cell[0] == '+') cell.remove_prefix(1);
  char buffer[9];
  for (size_t i = 0; i < cell.size(); ++i) {
    buffer[i] =
        static_cast<char>(std::tolower(static_cast<unsigned char>(cell[i])));
  }
  const std::string_view lower(buffer, cell.size());
  return lower == "#n/a" || lower == "#nv" || lower == "#na" ||
         lower == "n/a" || lower == "na" || lower == "null" ||
         lower == "nan(ind)" || lower == "1.#qnan" || lower == "1.#ind";
}

// Parses a whole cell as a number. Empty cell -> NaN (a gap); "nan" and the
// missing-value markers -> NaN. Returns false for text.
bool ParseCell(std::string_view cell, char decimal, double* value) {
  if (cell.empty() || IsMissingMarker(cell)) {
    *value = kNaN;
    return true;
  }
  if (cell.front() == '+') cell.remove_prefix(1);
  const auto result = fast_float::from_chars_advanced(
      cell.data(),
      cell.data() + cell.size(),
      *value,
      fast_float::parse_options{fast_float::chars_format::general, decimal});
  return result.ec == std::errc() && result.ptr == cell.data() + cell.size();
}

// Plain fixed-point decimals ("-12.3456"), the bulk of every tribometer
// export, parsed in the one pass that finds the field's end: a field of at
// most 15 digits, an optional '-' (after an optional '+') and one decimal
// mark, between optional blanks, ending at the delimiter or the end of the
// row. With at most 15 digits the mantissa is exact, and so is 10^k, so a
// single division rounds correctly (Clinger's fast path) and gives the
// double fast_float gives. Returns the delimiter's place (or the end), the
// value in *out; null for anything else (an empty field, an exponent, a
// long mantissa, nan, inf, text), which FastRow then takes the careful way.
inline const char* PlainField(
    const char* p, const char* end, char delim, char decimal, double* out) {
  const char* a = p;
  while (a < end && (*a == ' ' || *a == '\t')) ++a;
  if (a < end && *a == '+') ++a;
  bool negative = false;
  if (a < end && *a == '-') {
    negative = true;
    ++a;
  }
  std::uint64_t mantissa = 0;
  int digits = 0, fraction = 0;
  bool dot = false;
  for (; a < end; ++a) {
    const unsigned d = static_cast<unsigned char>(*a) - '0';
    if (d < 10) {
      if (++digits > 15) return nullptr;
      mantissa = mantissa * 10 + d;
      fraction += dot;
    } else if (*a == decimal && !dot) {
      dot = true;
    } else {
      break;
    }
  }
  if (digits == 0) return nullptr;
  while (a < end && (*a == ' ' || *a == '\t')) ++a;
  if (a < end && *a != delim) return nullptr;
  static constexpr double kPow10[] = {1e0,
                                      1e1,
                                      1e2,
                                      1e3,
                                      1e4,
                                      1e5,
                                      1e6,
                                      1e7,
                                      1e8,
                                      1e9,
                                      1e10,
                                      1e11,
                                      1e12,
                                      1e13,
                                      1e14,
                                      1e15};
  const double v = static_cast<double>(mantissa) / kPow10[fraction];
  *out = negative ? -v : v;
  return a;
}

// A time column written as a date and time of day: the seconds since the
// first data row's (the origin's) date and time.
struct Clock {
  int field = -1;      // the column, -1 = the time column holds numbers
  bool dated = false;  // a date with the time of day (else it may wrap)
  long origin_days = 0;
  double origin_seconds = 0;
};

// Days from 1970-01-01 of a proleptic Gregorian date (H. Hinnant's
// days_from_civil).
long DaysFromCivil(long y, unsigned m, unsigned d) {
  y -= m <= 2;
  const long era = (y >= 0 ? y : y - 399) / 400;
  const unsigned yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<long>(doe) - 719468;
}

// A date and time of day as instruments and LabVIEW rigs log them:
// "2024-05-01 12:00:00.125" (or with 'T'), "01.05.2024 12:00:00,125", or a
// time of day alone, "12:00:00.125" (seconds and their fraction optional
// after the minutes; a trailing 'Z' allowed). Days since 1970-01-01 (0
// without a date), seconds of the day, and whether a date was given. False
// for anything else (a '/' date, whose day and month order is unknowable).
bool ParseClock(std::string_view cell,
                long* days,
                double* seconds,
                bool* dated) {
  cell = TrimView(cell);
  const char* p = cell.data();
  const char* const end = p + cell.size();
  const auto number = [&](int min_digits, int max_digits, long* v) {
    int n = 0;
    *v = 0;
    while (p < end && n < max_digits && *p >= '0' && *p <= '9') {
      *v = *v * 10 + (*p++ - '0');
      ++n;
    }
    return n >= min_digits;
  };
  const auto take = [&](char c) {
    if (p < end && *p == c) {
      ++p;
      return true;
    }
    return false;
  };
  *days = 0;
  *dated = false;
  const char* start = p;
  long a = 0, b = 0, c = 0;
  if (number(4, 4, &a) && take('-') && number(2, 2, &b) && take('-') &&
      number(2, 2, &c) && (take(' ') || take('T'))) {
    if (b < 1 || b > 12 || c < 1 || c > 31) return false;
    *days =
        DaysFromCivil(a, static_cast<unsigned>(b), static_cast<unsigned>(c));
    *dated = true;
  } else {
    p = start;
    if (number(1, 2, &a) && take('.') && number(1, 2, &b) && take('.') &&
        number(4, 4, &c) && take(' ')) {
      if (b < 1 || b > 12 || a < 1 || a > 31) return false;
      *days =
          DaysFromCivil(c, static_cast<unsigned>(b), static_cast<unsigned>(a));
      *dated = true;
    } else {
      p = start;
    }
  }
  while (p < end && *p == ' ') ++p;
  long h = 0, m = 0, sec = 0;
  if (!(number(1, 2, &h) && take(':') && number(2, 2, &m))) return false;
  double fraction = 0;
  if (take(':')) {
    if (!number(2, 2, &sec)) return false;
    if (p < end && (*p == '.' || *p == ',')) {
      ++p;
      long digits = 0, scale = 1;
      int n = 0;
      while (p < end && *p >= '0' && *p <= '9' && n < 9) {
        digits = digits * 10 + (*p++ - '0');
        scale *= 10;
        ++n;
      }
      if (n == 0) return false;
      while (p < end && *p >= '0' && *p <= '9') ++p;  // beyond nanoseconds
      fraction = static_cast<double>(digits) / static_cast<double>(scale);
    }
  }
  take('Z');
  if (p != end || h > 23 || m > 59 || sec > 60) return false;
  *seconds = static_cast<double>(h * 3600 + m * 60 + sec) + fraction;
  return true;
}

// The clock's value of a cell: seconds since the origin; false if the
// cell is not a clock reading.
bool ClockSeconds(const Clock& clock, std::string_view cell, double* value) {
  long days;
  double seconds;
  bool dated;
  if (cell.empty() || IsMissingMarker(cell)) {
    *value = kNaN;
    return true;
  }
  if (!ParseClock(cell, &days, &seconds, &dated) || dated != clock.dated)
    return false;
  *value = static_cast<double>(days - clock.origin_days) * 86400.0 +
           (seconds - clock.origin_seconds);
  return true;
}

// One pass over a data row parsing only the fields that `slot_of_field`
// maps to a slot (-1: skip), trimming blanks. Returns false on anything the
// careful path must look at: quotes, text, or a field count other than
// `columns` (plus one empty field after a trailing delimiter).
bool FastRow(std::string_view row,
             char delim,
             char decimal,
             const std::vector<int>& slot_of_field,
             const Clock& clock,
             double* out) {
  const char* p = row.data();
  const char* const end = p + row.size();
  const size_t columns = slot_of_field.size();
  const fast_float::parse_options options{fast_float::chars_format::general,
                                          decimal};
  // (A decimal mark that is also the delimiter cannot end a field.)
  const bool plain = decimal != delim;
  size_t field = 0;
  for (;;) {
    if (static_cast<int>(field) == clock.field) {
      const char* q = p < end ? static_cast<const char*>(std::memchr(
                                    p, delim, static_cast<size_t>(end - p)))
                              : nullptr;
      if (q == nullptr) q = end;
      if (!ClockSeconds(clock,
                        std::string_view(p, static_cast<size_t>(q - p)),
                        &out[slot_of_field[field]]))
        return false;
      ++field;
      if (q == end) break;
      p = q + 1;
      continue;
    }
    if (plain && field < columns && slot_of_field[field] >= 0) {
      const char* q =
          PlainField(p, end, delim, decimal, &out[slot_of_field[field]]);
      if (q != nullptr) {
        ++field;
        if (q == end) break;
        p = q + 1;
        continue;
      }
    }
    const char* q = p < end ? static_cast<const char*>(std::memchr(
                                  p, delim, static_cast<size_t>(end - p)))
                            : nullptr;
    if (q == nullptr) q = end;
    if (field < columns && slot_of_field[field] >= 0) {
      const char* a = p;
      const char* b = q;
      while (a < b && (*a == ' ' || *a == '\t')) ++a;
      while (b > a && (b[-1] == ' ' || b[-1] == '\t')) --b;
      double& v = out[slot_of_field[field]];
      if (a == b) {
        v = kNaN;
      } else {
        if (*a == '+') ++a;
        const auto r = fast_float::from_chars_advanced(a, b, v, options);
        if (r.ec != std::errc() || r.ptr != b) return false;
      }
    }
    ++field;
    if (q == end) break;
    p = q + 1;
  }
  return field == columns ||
         (field == columns + 1 && !row.empty() && row.back() == delim);
}

// ---------------------------------------------------------------------------
// Layout detection on the first lines.

struct Layout {
  char delimiter = ',';
  char decimal = '.';
  int header_line = -1;  // index into head lines, -1 = no header
  int units_line = -1;
  int first_data_line = 0;
  std::vector<std::string> names;  // per column
  std::vector<std::string> units;  // per column ("" unknown)
  double metadata_rate_hz = 0.0;
  std::string kind = "delimited";
  // The first column holding a number in the first data row (0 but where
  // a text column, a status or a time of day, comes first): a row whose
  // cell there is text is a text line (a footer, a block's header).
  int first_number_column = 0;
};

// A data row: at least two numbers, and more numbers than text cells (a
// status or comment column the method does not use may hold text; a
// metadata line such as "Stroke,5.7,mm,Frequency,10,Hz" is not data).
bool IsNumericRow(std::string_view line,
                  char delim,
                  char decimal,
                  std::vector<std::string_view>* cells) {
  Split(line, delim, cells);
  int numeric = 0, text = 0;
  for (auto c : *cells) {
    double v;
    if (c.empty() || IsMissingMarker(c)) continue;
    if (ParseCell(c, decimal, &v)) {
      ++numeric;
    } else {
      ++text;
    }
  }
  return numeric >= 2 && text < numeric;
}

char DetectDelimiter(const std::vector<std::string>& head, int vote_lines) {
  // Data rows dominate the end of the head; a delimiter that splits them into
  // the same number (>= 2) of cells is the one. Tab and ';' win over ','
  // because ',' may be the decimal mark in those files.
  for (char d : {'\t', ';', ','}) {
    int lines = 0, consistent = 0;
    size_t expected = 0;
    for (auto it = head.rbegin(); it != head.rend() && lines < vote_lines;
         ++it) {
      if (it->empty()) continue;
      ++lines;
      const size_t n =
          static_cast<size_t>(std::count(it->begin(), it->end(), d));
      if (lines == 1) expected = n;
      if (n >= 1 && n == expected) ++consistent;
    }
    if (lines > 0 && expected >= 1 && consistent * 10 >= lines * 8) return d;
  }
  return ',';
}

bool LooksLikeUnit(std::string_view cell) {
  if (cell.empty()) return true;
  if ((cell.front() == '(' && cell.back() == ')') ||
      (cell.front() == '[' && cell.back() == ']')) {
    return true;
  }
  auto simple = [](std::string_view u) {
    const std::string l = Lower(u);
    return internal::LengthToMm(u) || internal::ForceToN(u) ||
           internal::TimeToS(u) || l == "hz" || l == "c" ||
           l == "\xb0"
                "c" ||
           l == "\xc2\xb0"
                "c" ||
           l == "%" || l == "-" || l == "()" || l == "deg" || l == "rpm" ||
           l == "v" || l == "mv" || l == "um" || l == "n/a" || l == "cycles" ||
           l == "cycle";
  };
  if (simple(cell)) return true;
  // Rates and ratios: "mm/sec" (CETR), "mm/s", "N/mm", "g/cm".
  const size_t slash = cell.find('/');
  return slash != std::string_view::npos && slash > 0 &&
         simple(cell.substr(0, slash)) && simple(cell.substr(slash + 1));
}

double FindMetadataRate(const std::vector<std::string>& lines, int end) {
  for (int i = 0; i < end; ++i) {
    const std::string lower = Lower(lines[i]);
    const bool names_rate =
        (lower.find("sampling") != std::string::npos ||
         lower.find("sample rate") != std::string::npos ||
         lower.find("acquisition rate") != std::string::npos ||
         lower.find("data rate") != std::string::npos);
    if (!names_rate) continue;
    // The first number after the label's end (':' or '=' or delimiter).
    size_t pos = lower.find_first_of(":=,;\t");
    if (pos == std::string::npos) continue;
    const char* p = lines[i].data() + pos + 1;
    const char* end_p = lines[i].data() + lines[i].size();
    while (p < end_p && !(std::isdigit(static_cast<unsigned char>(*p)))) ++p;
    double rate = 0.0;
    auto r = fast_float::from_chars(p, end_p, rate);
    if (r.ec != std::errc() || !(rate > 0)) continue;
    const bool khz = lower.find("khz") != std::string::npos;
    return khz ? rate * 1e3 : rate;
  }
  return 0.0;
}

// The decimal mark: with ';' or tab separators, ',' when more head rows
// read as numbers with it than with '.'.
char DetectDecimal(const std::vector<std::string>& head, char delimiter) {
  if (delimiter == ',') return '.';
  std::vector<std::string_view> cells;
  int dot_rows = 0, comma_rows = 0;
  for (const auto& line : head) {
    if (IsNumericRow(line, delimiter, '.', &cells)) ++dot_rows;
    if (IsNumericRow(line, delimiter, ',', &cells)) ++comma_rows;
  }
  return comma_rows > dot_rows ? ',' : '.';
}

// Which cells of a row hold text (not a number, a gap or a missing-value
// marker), and how many cells it has (without a trailing delimiter's empty
// one): the data rows of a file share one shape, a metadata line above
// them ("Load (N),30,10", "Created,2024,05,01") does not.
std::vector<bool> ShapeOf(const std::vector<std::string_view>& cells,
                          char decimal) {
  std::vector<bool> text(CountWithoutTrailing(cells));
  double v;
  for (size_t c = 0; c < text.size(); ++c)
    text[c] = !cells[c].empty() && !ParseCell(cells[c], decimal, &v);
  return text;
}

// The first data row: numeric and followed by numeric rows of its shape
// (or the end).
int FindFirstDataLine(const std::vector<std::string>& head,
                      const Layout& layout,
                      const std::string& name) {
  std::vector<std::string_view> cells;
  const int n = static_cast<int>(head.size());
  for (int i = 0; i < n; ++i) {
    if (!IsNumericRow(head[i], layout.delimiter, layout.decimal, &cells))
      continue;
    const std::vector<bool> shape = ShapeOf(cells, layout.decimal);
    int ok = 1;
    for (int j = i + 1; j < std::min(n, i + 4); ++j) {
      if (IsNumericRow(head[j], layout.delimiter, layout.decimal, &cells) &&
          ShapeOf(cells, layout.decimal) == shape)
        ++ok;
    }
    if (ok >= std::min(3, n - i)) return i;
  }
  throw ForceError(fmt::format(
      "{}: no numeric data found in the first {} lines; expected rows of at "
      "least two numbers separated by '{}'",
      name,
      n,
      layout.delimiter == '\t' ? "\\t" : std::string(1, layout.delimiter)));
}

// The header above the data, possibly with a units row between.
void FindHeaderAndUnits(const std::vector<std::string>& head, Layout* layout) {
  std::vector<std::string_view> cells;
  int above = layout->first_data_line - 1;
  while (above >= 0 && TrimView(head[above]).empty()) --above;
  if (above >= 0) {
    Split(head[above], layout->delimiter, &cells);
    const bool all_units =
        cells.size() >= 2 &&
        std::all_of(cells.begin(), cells.end(), LooksLikeUnit) &&
        std::any_of(cells.begin(), cells.end(), [](std::string_view c) {
          return !c.empty();
        });
    if (all_units && above >= 1) {
      layout->units_line = above;
      --above;
      while (above >= 0 && TrimView(head[above]).empty()) --above;
    }
  }
  if (above >= 0) {
    Split(head[above], layout->delimiter, &cells);
    if (cells.size() >= 2) layout->header_line = above;
  }
  if (layout->header_line < 0) layout->units_line = -1;
}

// Column names and units from the header ("Fx (N)") and the units row.
void ReadNamesAndUnits(const std::vector<std::string>& head, Layout* layout) {
  std::vector<std::string_view> cells;
  Split(head[layout->header_line >= 0 ? layout->header_line
                                      : layout->first_data_line],
        layout->delimiter,
        &cells);
  const size_t columns = CountWithoutTrailing(cells);
  layout->names.assign(columns, "");
  layout->units.assign(columns, "");
  if (layout->header_line >= 0) {
    Split(head[layout->header_line], layout->delimiter, &cells);
    for (size_t c = 0; c < std::min(columns, cells.size()); ++c) {
      internal::SplitNameAndUnit(
          cells[c], &layout->names[c], &layout->units[c]);
    }
  }
  if (layout->units_line >= 0) {
    Split(head[layout->units_line], layout->delimiter, &cells);
    for (size_t c = 0; c < std::min(columns, cells.size()); ++c) {
      std::string unit_name, unit;
      internal::SplitNameAndUnit(cells[c], &unit_name, &unit);
      const std::string u = unit.empty() ? unit_name : unit;
      if (!u.empty()) layout->units[c] = u;
    }
  }
}

// The layout's name for the record, by the rules in layouts.cc.
std::string LayoutKindOf(const Layout& layout) {
  internal::LayoutFacts facts;
  facts.delimiter = layout.delimiter;
  facts.units_row = layout.units_line >= 0;
  facts.metadata_rate_hz = layout.metadata_rate_hz;
  for (const auto& nm : layout.names) facts.names += Lower(nm) + "|";
  for (const auto& u : layout.units) facts.units += Lower(u) + "|";
  return internal::LayoutKind(facts);
}

Layout DetectLayout(const std::vector<std::string>& head,
                    const std::string& name,
                    const ReadForceOptions& options) {
  // ReadHead refuses an empty file.
  WEARSCAR_CHECK(!head.empty(), "DetectLayout needs the head lines");
  Layout layout;
  layout.delimiter = DetectDelimiter(head, options.delimiter_vote_lines);
  layout.decimal = DetectDecimal(head, layout.delimiter);
  layout.first_data_line = FindFirstDataLine(head, layout, name);
  {
    std::vector<std::string_view> cells;
    Split(head[layout.first_data_line], layout.delimiter, &cells);
    double v;
    while (layout.first_number_column + 1 < static_cast<int>(cells.size()) &&
           !ParseCell(cells[layout.first_number_column], layout.decimal, &v))
      ++layout.first_number_column;
  }
  FindHeaderAndUnits(head, &layout);
  ReadNamesAndUnits(head, &layout);
  layout.metadata_rate_hz = FindMetadataRate(
      head,
      layout.header_line >= 0 ? layout.header_line : layout.first_data_line);
  layout.kind = LayoutKindOf(layout);
  return layout;
}

// ---------------------------------------------------------------------------
// Column matching by pattern.

using internal::Channel;
using internal::kP;
using internal::kQ;
using internal::kTime;
using internal::kX;
using internal::MatchScore;
constexpr const char* kChannelLabel[] = {
    "time", "position x", "tangential force Q", "normal force P"};

int FindOverride(const std::string& spec,
                 const Layout& layout,
                 const std::string& file,
                 Channel channel) {
  if (spec.size() > 1 && spec[0] == '#') {
    int col = 0;
    auto r = std::from_chars(spec.data() + 1, spec.data() + spec.size(), col);
    if (r.ec != std::errc() || col < 1 ||
        col > static_cast<int>(layout.names.size())) {
      throw ForceError(
          fmt::format("{}: column override '{}' for {} is not a "
                      "column number between 1 and {}",
                      file,
                      spec,
                      kChannelLabel[channel],
                      layout.names.size()));
    }
    return col - 1;
  }
  // The name as the reader split it ("x" of "x_mm"), or as the header
  // wrote it with its unit: x_mm, "x (mm)", "x [mm]", x/mm.
  const std::string wanted = Lower(spec);
  std::string known;
  for (size_t c = 0; c < layout.names.size(); ++c) {
    const std::string name = Lower(layout.names[c]);
    const std::string unit =
        c < layout.units.size() ? Lower(layout.units[c]) : std::string();
    if (wanted == name) return static_cast<int>(c);
    if (!unit.empty()) {
      for (const std::string& form : {name + "_" + unit,
                                      name + " (" + unit + ")",
                                      name + " [" + unit + "]",
                                      name + "/" + unit}) {
        if (wanted == form) return static_cast<int>(c);
      }
    }
    known += (known.empty() ? "" : ", ") + layout.names[c];
    if (!unit.empty()) known += " (" + layout.units[c] + ")";
  }
  throw ForceError(
      fmt::format("{}: no column named '{}' for {}; the header has: {}",
                  file,
                  spec,
                  kChannelLabel[channel],
                  known));
}

// ---------------------------------------------------------------------------

struct Scale {
  double factor = 1.0;
  std::string unit;
  bool inferred = false;  // no unit in the file or options: infer at the end
};

std::optional<double> UnitFactor(Channel channel, const std::string& unit) {
  return channel == kTime ? internal::TimeToS(unit)
         : channel == kX  ? internal::LengthToMm(unit)
                          : internal::ForceToN(unit);
}

Scale ResolveUnit(Channel channel,
                  const std::string& found,
                  const ReadForceOptions& options,
                  const std::string& file,
                  const std::string& column,
                  std::vector<std::string>* warnings) {
  const std::string& given = channel == kTime ? options.time_unit
                             : channel == kX  ? options.x_unit
                                              : options.force_unit;
  const std::string unit = given.empty() ? found : given;
  if (unit.empty()) return {1.0, "", true};
  const std::optional<double> f = UnitFactor(channel, unit);
  if (!f) {
    const char* expected = channel == kTime ? "s, ms, min"
                           : channel == kX  ? "mm, um, m"
                                            : "N, mN, kN, gf";
    throw ForceError(
        fmt::format("{}: column '{}' has unit '{}'; expected a {} "
                    "unit ({})",
                    file,
                    internal::Printable(column),
                    internal::Printable(unit),
                    channel == kTime ? "time"
                    : channel == kX  ? "length"
                                     : "force",
                    expected));
  }
  if (!given.empty() && !found.empty()) {
    const std::optional<double> ff = UnitFactor(channel, found);
    if (!ff || std::abs(*ff - *f) > 1e-12 * std::abs(*f)) {
      warnings->push_back(
          fmt::format("column '{}' says '{}'; read as '{}' as the options ask",
                      column,
                      found,
                      given));
    }
  }
  return {*f, unit, false};
}

// Robust spread of a channel (99th minus 1st percentile of a subsample) and
// the median of its magnitude.
void Spread(const Eigen::VectorXd& v, double* span, double* median_abs) {
  std::vector<double> s, a;
  const Eigen::Index step = std::max<Eigen::Index>(1, v.size() / 20000);
  for (Eigen::Index i = 0; i < v.size(); i += step) {
    if (!std::isfinite(v[i])) continue;
    s.push_back(v[i]);
    a.push_back(std::abs(v[i]));
  }
  *span = *median_abs = std::nan("");
  if (s.empty()) return;
  auto at = [](std::vector<double>& w, double q) {
    const std::size_t k = static_cast<std::size_t>(q * (w.size() - 1));
    std::nth_element(w.begin(), w.begin() + k, w.end());
    return w[k];
  };
  *span = at(s, 0.99) - at(s, 0.01);
  *median_abs = at(a, 0.5);
}

// Units of the channels that state none, from plausibility: the first unit
// of a channel's list that brings its figure (stroke, median load, sampling
// rate) into the plausible range. The values are scaled in place; a warning
// names each assumption, and a channel no unit makes plausible is refused.
struct UnitGuess {
  const char* unit;
  double factor;  // to mm, N or s
};

struct Plausibility {
  std::vector<UnitGuess> units;
  double lo, hi;       // the figure's plausible range in mm, N or Hz
  bool divide;         // figure / factor (a rate) instead of figure * factor
  const char* range;   // "a stroke of 0.05-50 mm", for the refusal
  const char* option;  // the --columns key
};

const Plausibility& PlausibilityOf(Channel ch) {
  static const Plausibility kX_ = {{{"mm", 1.0}, {"um", 1e-3}, {"m", 1e3}},
                                   0.05,
                                   50,
                                   false,
                                   "a stroke of 0.05-50 mm",
                                   "x"};
  static const Plausibility kForce = {{{"N", 1.0}, {"mN", 1e-3}, {"kN", 1e3}},
                                      0.01,
                                      5000,
                                      false,
                                      "a load of 0.01-5000 N",
                                      "p"};
  static const Plausibility kTime_ = {
      {{"s", 1.0}, {"ms", 1e-3}, {"us", 1e-6}, {"min", 60.0}},
      1,
      1e6,
      true,
      "sampling at 1 Hz-1 MHz",
      "time"};
  return ch == kX ? kX_ : ch == kTime ? kTime_ : kForce;
}

// The first plausible unit for `figure`, or nullptr.
const UnitGuess* FirstPlausible(const Plausibility& p, double figure) {
  for (const UnitGuess& g : p.units) {
    const double v = p.divide ? figure / g.factor : figure * g.factor;
    if (v >= p.lo && v <= p.hi) return &g;
  }
  return nullptr;
}

// The figure a channel's unit is judged by, and how the message says it.
double Figure(Channel ch, const Eigen::VectorXd& v, std::string* said) {
  double span, median;
  if (ch == kTime) {
    const double raw = v.size() > 1 ? v[v.size() - 1] - v[0] : 0.0;
    const double rate = raw > 0 ? (v.size() - 1) / raw : 0.0;
    *said = fmt::format("its samples come {:.4g} per unit", rate);
    return rate;
  }
  Spread(v, &span, &median);
  if (ch == kX) {
    *said = fmt::format("its values span {:.4g}", span);
    return span;
  }
  *said = fmt::format("its median magnitude is {:.4g}", median);
  return median;
}

std::string Because(Channel ch, double scaled) {
  switch (ch) {
    case kX:
      return fmt::format(
          "a stroke of {:.3g} mm; tribometer strokes are 0.05-50 mm", scaled);
    case kTime:
      return fmt::format("sampling at {:.4g} Hz", scaled);
    default:
      return fmt::format("{} of {:.3g} N at the median; loads are 0.01-5000 N",
                         ch == kP ? "a load" : "a force",
                         scaled);
  }
}

void InferUnits(Eigen::VectorXd* data,
                Scale* scale,
                const int* column,
                const Layout& layout,
                const std::string& file,
                ForceMetadata* meta) {
  auto apply =
      [&](int ch, const char* unit, double factor, const std::string& because) {
        data[ch] *= factor;
        scale[ch] = {factor, unit, false};
        meta->warnings.push_back(
            fmt::format("column '{}' states no unit: taken as {} ({})",
                        layout.names[column[ch]],
                        unit,
                        because));
      };
  // x, then the forces (P first: Q without a unit takes P's when P's was
  // stated), then time.
  for (Channel ch : {kX, kP, kQ, kTime}) {
    if (column[ch] < 0 || !scale[ch].inferred) continue;
    if (ch == kQ && !scale[kP].unit.empty() && !scale[kP].inferred) {
      double span, median;
      Spread(data[kQ], &span, &median);
      apply(kQ,
            scale[kP].unit.c_str(),
            scale[kP].factor,
            fmt::format("the normal force's unit; |Q| {:.3g} N at the median",
                        median * scale[kP].factor));
      continue;
    }
    const Plausibility& p = PlausibilityOf(ch);
    std::string said;
    const double figure = Figure(ch, data[ch], &said);
    if (const UnitGuess* g = FirstPlausible(p, figure)) {
      apply(ch,
            g->unit,
            g->factor,
            Because(ch, p.divide ? figure / g->factor : figure * g->factor));
      continue;
    }
    std::string units;
    for (const UnitGuess& g : p.units) {
      units += (units.empty()           ? ""
                : &g == &p.units.back() ? " or "
                                        : ", ") +
               std::string(g.unit);
    }
    throw ForceError(fmt::format(
        "{}: column '{}' states no unit and {}: no unit makes it plausible "
        "({} as {}); give the unit (e.g. --columns {}=NAME:UNIT)",
        file,
        layout.names[column[ch]],
        said,
        p.range,
        units,
        ch == kQ ? "q" : p.option));
  }
}

// What a reciprocating tribometer can have measured: refused outside the
// hard limits (a unit or file error), warned of outside the usual ranges.
void CheckPlausible(ForceRecord& r, const std::string& file) {
  constexpr double kMaxForceN = 1e5, kMaxAbsXMm = 1e4;
  auto where = [&](Eigen::Index i) {
    return fmt::format("sample {} (t = {:.6g} s)", i + 1, r.time_s[i]);
  };
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    if (std::abs(r.tangential_n[i]) > kMaxForceN ||
        std::abs(r.normal_n[i]) > kMaxForceN) {
      throw ForceError(fmt::format(
          "{}: {}: a force of {:.4g} N; expected at most {:.0e} N in "
          "magnitude",
          file,
          where(i),
          std::abs(r.tangential_n[i]) > kMaxForceN ? r.tangential_n[i]
                                                   : r.normal_n[i],
          kMaxForceN));
    }
    if (std::abs(r.x_mm[i]) > kMaxAbsXMm) {
      throw ForceError(fmt::format(
          "{}: {}: x = {:.4g} mm; expected a position within +-{:.0e} mm "
          "(check the x unit)",
          file,
          where(i),
          r.x_mm[i],
          kMaxAbsXMm));
    }
  }
  double span, median;
  Spread(r.x_mm, &span, &median);
  if (!(span >= 0.01 && span <= 100)) {
    throw ForceError(fmt::format(
        "{}: a stroke of {:.4g} mm (robust peak to peak of x); expected 0.05 "
        "to 50 mm for a reciprocating test (check the x unit)",
        file,
        span));
  }
  if (span < 0.05 || span > 50) {
    r.metadata.warnings.push_back(fmt::format(
        "a stroke of {:.4g} mm, outside the usual 0.05-50 mm", span));
  }
  Spread(r.normal_n, &span, &median);
  if (!(median >= 1e-3)) {
    throw ForceError(fmt::format(
        "{}: the normal force is {:.3g} N at the median; expected a load (the "
        "method divides by it)",
        file,
        median));
  }
  if (median < 0.01 || median > 5000) {
    r.metadata.warnings.push_back(fmt::format(
        "a load of {:.4g} N at the median, outside the usual 0.01-5000 N",
        median));
  }
  const Eigen::Index n = r.size();
  const double duration = n > 1 ? r.time_s[n - 1] - r.time_s[0] : 0.0;
  const double rate = duration > 0 ? (n - 1) / duration : 0.0;
  if (!(rate >= 0.1 && rate <= 1e7)) {
    throw ForceError(fmt::format(
        "{}: {} samples over {:.4g} s: a sampling rate of {:.4g} Hz; expected "
        "0.1 Hz to 10 MHz (check the time column and its unit)",
        file,
        n,
        duration,
        rate));
  }
}

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

using Columns = std::array<int, 4>;  // per channel, -1 = absent

// The column of each channel: the ones the options name, then the best
// match by name among the columns left.
Columns ChooseColumns(const Layout& layout,
                      const ReadForceOptions& options,
                      const std::string& name) {
  Columns column = {-1, -1, -1, -1};
  const std::string* overrides[4] = {&options.time_column,
                                     &options.x_column,
                                     &options.tangential_column,
                                     &options.normal_column};
  // "none" for the time: no time column, the clock from the sampling rate.
  const bool no_time = Lower(options.time_column) == "none";
  for (int ch = 0; ch < 4; ++ch) {
    if (!overrides[ch]->empty() && !(ch == kTime && no_time)) {
      column[ch] = FindOverride(*overrides[ch], layout, name, Channel(ch));
    }
  }
  for (int ch = 0; ch < 4; ++ch) {
    if (column[ch] >= 0 || (ch == kTime && no_time)) continue;
    int best = -1, best_score = 0;
    for (int c = 0; c < static_cast<int>(layout.names.size()); ++c) {
      if (std::find(column.begin(), column.end(), c) != column.end()) continue;
      const int s = MatchScore(Channel(ch), layout.names[c]);
      if (s > best_score) best = c, best_score = s;
    }
    column[ch] = best;
  }
  return column;
}

// What the method needs: a reciprocating displacement and the two forces.
// Refuses a file without them, saying what it has.
void RequireChannels(const Columns& column,
                     const Layout& layout,
                     const std::string& name) {
  std::vector<std::string> missing;
  for (int ch = kX; ch <= kP; ++ch) {
    if (column[ch] < 0) missing.push_back(kChannelLabel[ch]);
  }
  if (missing.empty()) return;
  std::string known;
  for (const auto& nm : layout.names) known += (known.empty() ? "" : ", ") + nm;
  if (layout.header_line < 0) known = "(no header row)";
  bool has_cof = false;
  for (const auto& nm : layout.names)
    has_cof |= internal::IsComputedCoefficient(nm);
  std::string list;
  for (size_t i = 0; i < missing.size(); ++i) {
    list += (i == 0                    ? ""
             : i + 1 == missing.size() ? " or "
                                       : ", ") +
            missing[i];
  }
  throw ForceError(fmt::format(
      "{}: line {}: no column for {}; the method needs a reciprocating "
      "displacement and the tangential and normal forces, and the file "
      "has: {}{} ({})",
      name,
      (layout.header_line >= 0 ? layout.header_line : 0) + 1,
      list,
      known,
      has_cof && column[kQ] < 0
          ? "; a friction coefficient alone cannot carry the method"
          : "",
      layout.header_line < 0
          ? "name the columns by number, e.g. --columns "
            "time=#1,x=#2,q=#3,p=#4"
          : "give a column explicitly if it is there under another name, "
            "e.g. --columns x=NAME"));
}

// The channels' columns hold numbers in the first data rows: a column the
// method would read that holds text there (a time of day, a status) is
// refused here, naming it, rather than as every row's error.
void RequireNumbers(const std::vector<std::string>& head,
                    const Columns& column,
                    const Layout& layout,
                    const Clock& clock,
                    const std::string& name) {
  std::vector<std::string_view> cells;
  const int n = static_cast<int>(head.size());
  for (int i = layout.first_data_line;
       i < std::min(n, layout.first_data_line + 3);
       ++i) {
    Split(head[i], layout.delimiter, &cells);
    for (int ch = 0; ch < 4; ++ch) {
      if (column[ch] < 0 || column[ch] >= static_cast<int>(cells.size()))
        continue;
      const std::string_view cell = cells[column[ch]];
      double value;
      if (column[ch] == clock.field ? ClockSeconds(clock, cell, &value)
                                    : ParseCell(cell, layout.decimal, &value))
        continue;
      throw ForceError(fmt::format(
          "{}: line {}, column {} ('{}', taken as {}): found text '{}'; "
          "expected a number{} (give the {} column explicitly if another "
          "holds it{})",
          name,
          i + 1,
          column[ch] + 1,
          internal::Printable(layout.names[column[ch]]),
          kChannelLabel[ch],
          internal::Printable(cell),
          layout.decimal == ',' ? " with a decimal comma" : "",
          kChannelLabel[ch],
          ch == kTime ? ", or --time-column none and the sampling rate" : ""));
    }
  }
}

// The time column as a clock when its first data cell is a date and time
// of day or a time of day (not a number): its origin that cell's.
Clock FindClock(const std::vector<std::string>& head,
                const Columns& column,
                const Layout& layout) {
  Clock clock;
  if (column[kTime] < 0) return clock;
  std::vector<std::string_view> cells;
  Split(head[layout.first_data_line], layout.delimiter, &cells);
  if (column[kTime] >= static_cast<int>(cells.size())) return clock;
  const std::string_view cell = cells[column[kTime]];
  double number;
  if (ParseCell(cell, layout.decimal, &number)) return clock;
  if (ParseClock(cell, &clock.origin_days, &clock.origin_seconds, &clock.dated))
    clock.field = column[kTime];
  return clock;
}

// A RecipeStep column lets the Rtec clock restart; -1 when none.
int FindStepColumn(const Layout& layout) {
  int step_column = -1;
  for (int c = 0; c < static_cast<int>(layout.names.size()); ++c) {
    if (internal::IsStepColumn(layout.names[c])) step_column = c;
  }
  return step_column;
}

// The data rows into columns, in N, mm and s on one clock. Ordinary rows go
// a fast path; anything unusual the careful way, which also joins restarted
// clocks (Rtec RecipeSteps, Bruker/CETR repeated blocks) and tells bad rows
// inside the data (an error, or dropped when lenient) from a text footer.
class RowReader {
 public:
  RowReader(const Layout& layout,
            const std::string* header_text,
            const Columns& column,
            int step_column,
            const Clock& clock,
            const Scale* scale,
            const ReadForceOptions& options,
            const std::string& name,
            Eigen::Index capacity,
            Eigen::Index expected_rows,
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
        slot_of_field_(columns_, -1) {
    std::vector<std::pair<void*, std::size_t>> buffers;
    for (int ch = 0; ch < 4; ++ch) {
      if (column_[ch] < 0) continue;
      data_[ch].resize(capacity);
      support::AdviseHugePages(data_[ch].data(),
                               sizeof(double) * data_[ch].size());
      buffers.emplace_back(data_[ch].data(),
                           sizeof(double) * static_cast<std::size_t>(std::min(
                                                expected_rows, capacity)));
    }
    // The columns' pages mapped beside the parsing (joined before they grow
    // and in Finish).
    prefault_.Start(std::move(buffers));
    // Fast path slots: the four channels, the RecipeStep column, and the
    // first field that holds a number (text there means a footer or a bad
    // row).
    if (layout.first_number_column < static_cast<int>(columns_))
      slot_of_field_[layout.first_number_column] = kFirstSlot;
    for (int ch = 0; ch < 4; ++ch) {
      if (column_[ch] >= 0 && column_[ch] < static_cast<int>(columns_))
        slot_of_field_[column_[ch]] = ch;
    }
    if (step_column_ >= 0 && step_column_ < static_cast<int>(columns_)) {
      slot_of_field_[step_column_] = kStepSlot;
    }
    fast_possible_ = needed_ < static_cast<int>(columns_);
  }

  void Handle(std::string_view row, long line_no) {
    if (fast_possible_ && pending_bad_rows_ == 0 && TryFast(row, line_no)) {
      return;
    }
    if (TrimView(row).empty() || SkipRepeatedBlock(row)) return;
    double value[4] = {kNaN, kNaN, kNaN, kNaN};
    bool text_row = false;
    std::string error = ParseCells(value, &text_row, line_no);
    if (error.empty() && column_[kTime] >= 0) {
      error = JoinClock(value, line_no);
    }
    if (!error.empty()) {
      if (pending_error_.empty()) pending_error_ = error;
      ++pending_bad_rows_;
      footer_rows_ += text_row ? 1 : 0;
      if (!text_row) footer_rows_ = -1000000;  // a numeric bad row: no footer
      return;
    }
    if (pending_bad_rows_ > 0) DropPending();
    Store(value, line_no);
  }

  // The ordinary rows of a stretch of the file parsed on their own
  // (ParseFastRows), and what joining them needs of them.
  struct FastRows {
    Eigen::Index rows = 0;  // stored from the row they were parsed to
    long next_offset = -1;  // the file offset of the first line not taken
    double first_time = kNaN, last_time = kNaN;
    double last_dt = kNaN;  // between their last two finite times
    double last_step = kNaN;
    int leading_nan[4] = {0, 0, 0, 0}, trailing_nan[4] = {0, 0, 0, 0};
  };

  // Parses the lines of `source` into the columns from row `at` on, as
  // TryFast and Store would take them one after another, up to the first
  // line they would not take on their own (a row of the careful path, a
  // step back in time, a run of missing values longer than allowed) or the
  // end. For a second thread while Handle reads the lines before: it reads
  // only what no row changes and writes only the columns' rows from `at`
  // (more than Handle can reach).
  //
  // `room` is the columns as they were before the first thread read a row:
  // that thread's rows stay below `at`, so it cannot grow the columns while
  // this one writes at `at` and beyond, short of their capacity.
  struct Room {
    double* column[4] = {nullptr, nullptr, nullptr, nullptr};
    Eigen::Index capacity = 0;
  };
  Room Reserved() {
    Room r;
    r.capacity = std::numeric_limits<Eigen::Index>::max();
    for (int ch = 0; ch < 4; ++ch) {
      if (column_[ch] < 0) continue;
      r.column[ch] = data_[ch].data();
      r.capacity = std::min(r.capacity, data_[ch].size());
    }
    return r;
  }
  FastRows ParseFastRows(FileLines& source, Eigen::Index at, const Room& room) {
    FastRows f;
    const bool timed = column_[kTime] >= 0;
    double previous = -std::numeric_limits<double>::infinity();
    int run[4] = {0, 0, 0, 0};
    bool finite[4] = {false, false, false, false};
    const Eigen::Index capacity = room.capacity;
    std::string_view row;
    for (;;) {
      f.next_offset = source.Offset();
      if (!fast_possible_ || at + f.rows >= capacity || !source.Next(&row))
        break;
      double v[6] = {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
      if (!FastRow(row,
                   layout_.delimiter,
                   layout_.decimal,
                   slot_of_field_,
                   clock_,
                   v))
        break;
      // TryFast's time with no clock joined (AdoptFastRows checks that).
      const double t = timed ? v[kTime] * scale_[kTime].factor + 0.0 : 0;
      if (timed && std::isfinite(t) && t <= previous) break;
      double x[4] = {kNaN, kNaN, kNaN, kNaN};
      bool too_long = false;
      for (int ch = 0; ch < 4; ++ch) {
        if (column_[ch] < 0) continue;
        x[ch] = ch == kTime ? t : v[ch] * scale_[ch].factor;
        too_long |= std::isnan(x[ch]) && run[ch] + 1 > options_.max_nan_run;
      }
      if (too_long) break;
      for (int ch = 0; ch < 4; ++ch) {
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
    for (int ch = 0; ch < 4; ++ch) f.trailing_nan[ch] = run[ch];
    return f;
  }

  // Takes the rows ParseFastRows put from row `at` as the rows after those
  // Handle has read, when one pass would have read them the same: nothing
  // pending, no clock joined, the first of their times after the last
  // read, the runs of missing values across the join within bounds. Moves
  // them to follow the rows read (fewer where lines were blank or
  // dropped). Returns false, changing nothing, otherwise.
  bool AdoptFastRows(const FastRows& f, Eigen::Index at) {
    if (f.rows == 0 || pending_bad_rows_ > 0 || time_offset_ != 0.0 ||
        rows_stored_ > at)
      return false;
    const bool timed = column_[kTime] >= 0;
    if (timed && std::isfinite(f.first_time) && f.first_time <= previous_time_)
      return false;
    for (int ch = 0; ch < 4; ++ch) {
      if (column_[ch] >= 0 &&
          nan_run_[ch] + f.leading_nan[ch] > options_.max_nan_run)
        return false;
    }
    for (int ch = 0; ch < 4; ++ch) {
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
    return true;
  }

  // After the last row: the bad rows left are a footer, an error or
  // dropped; the counts are checked. Returns the columns, trimmed.
  std::array<Eigen::VectorXd, 4> Finish() {
    prefault_.Stop();
    if (pending_bad_rows_ > 0) {
      if (footer_rows_ == pending_bad_rows_) {
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
            meta_->warnings.empty() ? pending_error_
                                    : meta_->warnings.front()));
      }
      meta_->warnings.push_back(fmt::format("dropped {} bad rows", dropped_));
    }
    for (int ch = 0; ch < 4; ++ch) {
      if (column_[ch] >= 0) data_[ch].conservativeResize(rows_stored_);
    }
    return std::move(data_);
  }

 private:
  static constexpr int kStepSlot = 4, kFirstSlot = 5;

  // The ordinary row: all fields numbers, time after the previous one.
  bool TryFast(std::string_view row, long line_no) {
    double v[6] = {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
    if (!FastRow(row,
                 layout_.delimiter,
                 layout_.decimal,
                 slot_of_field_,
                 clock_,
                 v)) {
      return false;
    }
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

  // A repeated block (Bruker/CETR: every test step repeats its header
  // block, names row, units row, then data whose clock restarts): the names
  // row again ends the text lines before it, which were that block's
  // header, not bad rows; the text up to the next data row is skipped and
  // the clock may restart once. Splits the row into cells_ otherwise.
  bool SkipRepeatedBlock(std::string_view row) {
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
  std::string ParseCells(double* value, bool* text_row, long line_no) {
    double first_value;
    const size_t probe =
        cells_.empty()
            ? 0
            : std::min(static_cast<size_t>(layout_.first_number_column),
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
          internal::Printable(cells_[0]));
    }
    if (static_cast<int>(cells_.size()) <= needed_ ||
        (cells_.size() != columns_ && !trailing_ok)) {
      return fmt::format(
          "{}: line {}: ragged row: found {} fields, expected {}",
          name_,
          line_no,
          cells_.size(),
          columns_);
    }
    for (int ch = 0; ch < 4; ++ch) {
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
            internal::Printable(cell),
            layout_.decimal == ',' ? " with a decimal comma" : "");
      }
    }
    return {};
  }

  // Time on the joined clock: a clock that restarts with a new RecipeStep
  // or a repeated block continues; any other step back is an error.
  std::string JoinClock(double* value, long line_no) {
    double t = value[kTime] * scale_[kTime].factor + time_offset_;
    double step = kNaN;
    if (step_column_ >= 0 && step_column_ < static_cast<int>(cells_.size())) {
      ParseCell(cells_[step_column_], layout_.decimal, &step);
    }
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
    if (step_column_ >= 0 && step_column_ < static_cast<int>(cells_.size())) {
      ParseCell(cells_[step_column_], layout_.decimal, &previous_step_);
    }
    return {};
  }

  // Bad rows followed by a good one: an error, or dropped when lenient.
  void DropPending() {
    if (!options_.lenient) throw ForceError(pending_error_);
    dropped_ += pending_bad_rows_;
    if (meta_->warnings.empty() || dropped_ == pending_bad_rows_) {
      meta_->warnings.push_back("first dropped row: " + pending_error_);
    }
    pending_error_.clear();
    pending_bad_rows_ = 0;
    footer_rows_ = 0;
  }

  // One accepted row: time already on the joined clock, the other channels
  // converted to N and mm here; runs of missing values are bounded.
  void Store(const double* values, long line_no) {
    for (int ch = 0; ch < 4; ++ch) {
      if (column_[ch] < 0) continue;
      const double x =
          ch == kTime ? values[ch] : values[ch] * scale_[ch].factor;
      if (std::isnan(x)) {
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

  const Layout& layout_;
  const std::string* header_text_;
  const Columns column_;
  const int step_column_;
  const Clock clock_;
  const Scale* scale_;
  const ReadForceOptions& options_;
  const std::string& name_;
  ForceMetadata* meta_;
  const size_t columns_;
  const int needed_;
  std::vector<int> slot_of_field_;
  bool fast_possible_ = false;

  std::array<Eigen::VectorXd, 4> data_;
  // After data_: stopped before the columns are freed.
  support::BackgroundPrefault prefault_;
  Eigen::Index rows_stored_ = 0;
  std::vector<std::string_view> cells_;
  std::string pending_error_;
  int pending_bad_rows_ = 0, dropped_ = 0, footer_rows_ = 0, total_rows_ = 0;
  double previous_time_ = -std::numeric_limits<double>::infinity();
  double time_offset_ = 0.0, last_dt_ = 0.0, previous_step_ = kNaN;
  bool in_repeated_header_ = false, block_restart_ = false;
  int nan_run_[4] = {0, 0, 0, 0};
};

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
    if (std::isfinite(record->normal_n[i])) {
      finite.push_back(record->normal_n[i]);
    }
  }
  if (finite.empty()) return;
  std::nth_element(
      finite.begin(), finite.begin() + finite.size() / 2, finite.end());
  if (finite[finite.size() / 2] < 0) {
    record->normal_n = -record->normal_n;
    record->metadata.normal_sign_flipped = true;
  }
}

// The lines of a file (line breaks + 1) and, when asked for, the first line
// that starts after a byte offset: where a second thread may begin (with
// `to_split`, counted only that far, the file left where it stopped).
struct LineCount {
  size_t lines = 1;
  long split_offset = -1;  // that line's offset (-1: none asked or found)
  long lines_before_split = 0;
};

LineCount CountLines(
    std::FILE* file,
    const std::function<void(const char*, std::size_t)>& on_bytes,
    long split_at,
    bool to_split = false) {
  std::vector<char> block(size_t{1} << 20);
  LineCount count;
  long block_offset = 0;
  size_t got;
  while ((got = std::fread(block.data(), 1, block.size(), file)) > 0) {
    if (on_bytes) on_bytes(block.data(), got);
    const char* p = block.data();
    const char* end = p + got;
    while ((p = static_cast<const char*>(std::memchr(p, '\n', end - p))) !=
           nullptr) {
      ++count.lines;
      ++p;
      const long next = block_offset + (p - block.data());
      if (split_at >= 0 && count.split_offset < 0 && next > split_at) {
        count.split_offset = next;
        count.lines_before_split = static_cast<long>(count.lines) - 1;
        if (to_split) return count;
      }
    }
    block_offset += static_cast<long>(got);
  }
  std::rewind(file);
  return count;
}

ForceRecord Read(LineSource& source,
                 const std::string& name,
                 size_t row_capacity_hint,
                 const ReadForceOptions& options,
                 const SplitPoint* split = nullptr,
                 std::uintmax_t file_bytes = 0) {
  std::string why;
  if (!options.IsValid(&why)) {
    throw ForceError(fmt::format("{}: invalid read options: {}", name, why));
  }
  bool more = true;
  const std::vector<std::string> head =
      ReadHead(source, name, options.head_lines, &more);
  const Layout layout = DetectLayout(head, name, options);
  const Columns column = ChooseColumns(layout, options, name);
  RequireChannels(column, layout, name);
  const Clock clock = FindClock(head, column, layout);
  RequireNumbers(head, column, layout, clock, name);

  ForceRecord record;
  ForceMetadata& meta = record.metadata;
  meta.source = name;
  meta.layout = layout.kind;
  Scale scale[4];
  for (int ch = 0; ch < 4; ++ch) {
    if (column[ch] < 0) continue;
    scale[ch] = ch == kTime && clock.field >= 0
                    ? Scale{1.0, "s", false}  // a clock's seconds
                    : ResolveUnit(Channel(ch),
                                  layout.units[column[ch]],
                                  options,
                                  name,
                                  layout.names[column[ch]],
                                  &meta.warnings);
  }
  // Storage: exact capacity when the caller counted rows; else, for a file
  // of known size, room for as many rows as its shortest data line in the
  // head allows (untouched memory costs nothing; the columns are trimmed
  // in place), grown should that fall short. Mapped ahead of the parsing:
  // only the rows its longest data line allows, never pages it will not
  // fill.
  size_t capacity = row_capacity_hint, expected = row_capacity_hint;
  if (capacity == 0 && file_bytes > 0) {
    // (Blank lines are no measure of a row; none is shorter than "1,2".)
    constexpr size_t kShortestRow = 4;
    size_t head_bytes = 0, shortest = 0, longest = 0, data_lines = 0;
    for (size_t i = 0; i < head.size(); ++i) {
      const size_t bytes = head[i].size() + 1;  // its line break at least
      head_bytes += bytes;
      if (static_cast<int>(i) < layout.first_data_line) continue;
      ++data_lines;
      if (TrimView(head[i]).empty()) continue;
      shortest = shortest == 0 ? bytes : std::min(shortest, bytes);
      longest = std::max(longest, bytes);
    }
    const size_t rest = file_bytes > head_bytes ? file_bytes - head_bytes : 0;
    capacity = data_lines + rest / std::max(shortest, kShortestRow) + 16;
    // (CRLF lines are a byte longer than counted: fewer still.)
    expected = longest > 0 ? data_lines + rest / (longest + 1) : 0;
  }
  RowReader rows(layout,
                 layout.header_line >= 0 ? &head[layout.header_line] : nullptr,
                 column,
                 FindStepColumn(layout),
                 clock,
                 scale,
                 options,
                 name,
                 static_cast<Eigen::Index>(std::max<size_t>(capacity, 16)),
                 static_cast<Eigen::Index>(std::max<size_t>(expected, 16)),
                 &meta);
  long line_no = 0;
  for (const auto& h : head) {
    ++line_no;
    if (line_no - 1 >= layout.first_data_line) rows.Handle(h, line_no);
  }
  std::string_view line;
  // A second thread parses the ordinary rows from the split point on
  // (finding it first, if need be, by counting the lines before it) while
  // this one reads the lines before it; only after the head.
  if (split != nullptr && more) {
    const long head_lines = line_no;
    const RowReader::Room room = rows.Reserved();
    RowReader::FastRows second;
    long offset = split->offset, before = split->lines_before;
    bool second_ok = false;
    std::thread thread([&] {
      try {
        std::unique_ptr<std::FILE, FileCloser> file(
            std::fopen(split->path.c_str(), "rb"));
        if (!file) return;
        if (offset < 0) {
          const LineCount count =
              CountLines(file.get(), {}, split->middle, /*to_split=*/true);
          offset = count.split_offset;
          before = count.lines_before_split;
        }
        if (offset < 0 || before <= head_lines) return;
        FileLines lines(file.get(), split->path, options.max_line_bytes);
        lines.SeekTo(offset, before);
        second =
            rows.ParseFastRows(lines, before - layout.first_data_line, room);
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
    while (split->lines->Offset() <= split->middle && source.Next(&line))
      rows.Handle(line, ++line_no);
    thread.join();
    if (second_ok && line_no == before && split->lines->Offset() == offset &&
        rows.AdoptFastRows(second, before - layout.first_data_line)) {
      line_no += second.rows;
      split->lines->SeekTo(second.next_offset, line_no);
    }
  }
  if (more) {
    while (source.Next(&line)) rows.Handle(line, ++line_no);
  }
  std::array<Eigen::VectorXd, 4> data = rows.Finish();
  InferUnits(data.data(), scale, column.data(), layout, name, &meta);
  for (int ch = 0; ch < 4; ++ch) {
    meta.channel_names.push_back(column[ch] >= 0 ? layout.names[column[ch]]
                                                 : "");
    meta.channel_units.push_back(column[ch] >= 0 ? scale[ch].unit : "");
  }
  record.x_mm = std::move(data[kX]);
  record.tangential_n = std::move(data[kQ]);
  record.normal_n = std::move(data[kP]);
  SetTime(&record, &data[kTime], layout, options, name);
  CheckPlausible(record, name);
  MakeCompressionPositive(&record);
  return record;
}

}  // namespace

bool ReadForceOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (sampling_rate_hz < 0) return fail("sampling_rate_hz must be >= 0");
  if (!(max_dropped_fraction >= 0 && max_dropped_fraction <= 1)) {
    return fail("max_dropped_fraction must be in [0, 1]");
  }
  if (max_nan_run < 0) return fail("max_nan_run must be >= 0");
  if (max_line_bytes < 64) return fail("max_line_bytes must be >= 64");
  if (threads < 1) return fail("threads must be >= 1");
  if (head_lines < 2 || head_lines > 100000)
    return fail("head_lines must be 2 to 100000");
  if (delimiter_vote_lines < 1)
    return fail("delimiter_vote_lines must be >= 1");
  if (!x_unit.empty() && !internal::LengthToMm(x_unit))
    return fail("the x unit is not a length unit (mm, um, m, ...)");
  if (!force_unit.empty() && !internal::ForceToN(force_unit))
    return fail("the force unit is not a force unit (N, mN, kN, gf, ...)");
  if (!time_unit.empty() && !internal::TimeToS(time_unit))
    return fail("the time unit is not a time unit (s, ms, min, ...)");
  return true;
}

namespace {

// UTF-16 text (a byte order mark, or a NUL beside each of the first two
// ASCII bytes) from its first bytes, as iconv names its encoding; null for
// anything else.
const char* Utf16Encoding(std::string_view first) {
  const auto b = [&](size_t i) {
    return i < first.size() ? static_cast<unsigned char>(first[i]) : 0u;
  };
  if (first.size() >= 2 && b(0) == 0xFF && b(1) == 0xFE) return "UTF-16LE";
  if (first.size() >= 2 && b(0) == 0xFE && b(1) == 0xFF) return "UTF-16BE";
  const auto ascii = [](unsigned c) { return c >= 0x09 && c < 0x7F; };
  if (first.size() < 4) return nullptr;
  if (ascii(b(0)) && b(1) == 0 && ascii(b(2)) && b(3) == 0) return "UTF-16LE";
  if (b(0) == 0 && ascii(b(1)) && b(2) == 0 && ascii(b(3))) return "UTF-16BE";
  return nullptr;
}

// UTF-16 text as UTF-8 (what Excel's "Unicode Text" and some instruments'
// Windows software write), read block by block from `read` (bytes into a
// buffer, 0 at the end), each block to `on_bytes` as it is. At most
// kEstimateMaxBytes; an ill-formed or cut sequence is refused at its byte
// offset.
std::string Utf16ToUtf8(const std::function<size_t(char*, size_t)>& read,
                        const char* encoding,
                        const std::string& name,
                        std::uintmax_t size_hint,
                        const ReadForceOptions& options) {
  const auto too_large = [&](std::uintmax_t bytes) {
    return ForceError(fmt::format(
        "{}: more than {} bytes of {} text; expected at most {} MiB of "
        "UTF-16 (convert it to UTF-8 first, e.g. iconv -f UTF-16 -t UTF-8)",
        name,
        bytes,
        encoding,
        kEstimateMaxBytes >> 20));
  };
  if (size_hint > static_cast<std::uintmax_t>(kEstimateMaxBytes))
    throw too_large(size_hint);
  const iconv_t cd = iconv_open("UTF-8", encoding);
  if (cd == reinterpret_cast<iconv_t>(-1)) {
    throw ForceError(
        fmt::format("{}: {} text, which this system cannot convert: {}",
                    name,
                    encoding,
                    std::strerror(errno)));
  }
  struct Closer {
    iconv_t cd;
    ~Closer() { iconv_close(cd); }
  } closer{cd};
  std::string out;
  out.reserve(static_cast<size_t>(size_hint / 2 + 16));
  // Blocks of 1 MiB (less for a small text; 16 bytes at least, room for a
  // cut sequence and one whole), converted into twice as much.
  const size_t block = static_cast<size_t>(
      std::clamp<std::uintmax_t>(size_hint + 16, 16, std::uintmax_t{1} << 20));
  std::vector<char> in(block), converted(2 * block);
  size_t carry = 0;         // bytes of a sequence cut by the block's end
  std::uintmax_t done = 0;  // bytes converted before `in`
  for (;;) {
    const size_t got = read(in.data() + carry, in.size() - carry);
    if (got > 0 && options.on_bytes) options.on_bytes(in.data() + carry, got);
    if (done + carry + got > static_cast<std::uintmax_t>(kEstimateMaxBytes))
      throw too_large(done + carry + got);
    if (got == 0) {
      if (carry > 0) {
        throw ForceError(fmt::format(
            "{}: byte {}: the {} text ends inside a character; expected "
            "whole 2-byte units",
            name,
            done,
            encoding));
      }
      return out;
    }
    char* ip = in.data();
    size_t left = carry + got;
    while (left > 0) {
      char* op = converted.data();
      size_t room = converted.size();
      const size_t r = iconv(cd, &ip, &left, &op, &room);
      out.append(converted.data(), converted.size() - room);
      if (r != static_cast<size_t>(-1)) continue;
      if (errno == E2BIG) continue;
      if (errno == EINVAL) break;  // cut by the block: the next read ends it
      throw ForceError(fmt::format(
          "{}: byte {}: not valid {} text (an unpaired surrogate or an "
          "ill-formed unit); expected UTF-16, or save the file as UTF-8",
          name,
          done + static_cast<std::uintmax_t>(ip - in.data()),
          encoding));
    }
    done += static_cast<std::uintmax_t>(ip - in.data());
    carry = left;
    std::memmove(in.data(), ip, carry);
  }
}

// A workbook or document instead of text, by its magic bytes: refused with
// what it is and what to do (a spreadsheet saved as such rather than as
// CSV is a common first attempt).
void RefuseWorkbook(std::string_view first, const std::string& name) {
  const char* what = nullptr;
  if (first.substr(0, 4) == std::string_view("PK\x03\x04", 4)) {
    what = "a ZIP container (an Excel .xlsx or OpenDocument .ods workbook?)";
  } else if (first.substr(0, 8) ==
             std::string_view("\xD0\xCF\x11\xE0\xA1\xB1\x1A\xE1", 8)) {
    what = "an OLE2 compound file (an Excel .xls workbook?)";
  } else if (first.substr(0, 5) == "%PDF-") {
    what = "a PDF document";
  }
  if (what == nullptr) return;
  throw ForceError(fmt::format(
      "{}: byte 0: found {}; expected a delimited text export (save the "
      "sheet as CSV, or export text from the instrument's software)",
      name,
      what));
}

// Lines ended by CR alone (Excel's "CSV (Macintosh)", classic Mac OS):
// a CR and no LF in the first 64 KiB.
bool EndsLinesWithCrAlone(std::string_view first) {
  first = first.substr(0, size_t{64} << 10);
  return first.find('\r') != std::string_view::npos &&
         first.find('\n') == std::string_view::npos;
}

}  // namespace

ForceRecord ReadForceFile(const std::string& path,
                          const ReadForceOptions& options) {
  // A FIFO would block on open, /dev/zero never end: regular files only.
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!ec && !std::filesystem::is_regular_file(status)) {
    const auto type = status.type();
    throw ForceError(fmt::format(
        "{}: not a regular file ({}); expected a force export",
        path,
        type == std::filesystem::file_type::directory   ? "a directory"
        : type == std::filesystem::file_type::fifo      ? "a FIFO"
        : type == std::filesystem::file_type::character ? "a character device"
        : type == std::filesystem::file_type::block     ? "a block device"
        : type == std::filesystem::file_type::socket    ? "a socket"
        : type == std::filesystem::file_type::not_found ? "not found"
                                                        : "not a file"));
  }
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) {
    throw ForceError(
        fmt::format("{}: cannot open: {}", path, std::strerror(errno)));
  }
  std::error_code size_error;
  const std::uintmax_t size = std::filesystem::file_size(path, size_error);
  // What the first 64 KiB tell: a workbook (refused), UTF-16 text or lines
  // ended by CR alone (read whole, their bytes handed on as read, then
  // read as text); else the streaming reader below.
  std::string first(size_t{64} << 10, '\0');
  first.resize(std::fread(first.data(), 1, first.size(), file.get()));
  std::rewind(file.get());
  RefuseWorkbook(first, path);
  const char* encoding = Utf16Encoding(first);
  if (encoding != nullptr || EndsLinesWithCrAlone(first)) {
    std::FILE* f = file.get();
    const auto read = [&](char* into, size_t room) {
      const size_t n = std::fread(into, 1, room, f);
      if (n == 0 && std::ferror(f)) {
        throw ForceError(
            fmt::format("{}: read error: {}", path, std::strerror(errno)));
      }
      return n;
    };
    std::string text;
    if (encoding != nullptr) {
      text = Utf16ToUtf8(read,
                         encoding,
                         path,
                         size_error ? std::uintmax_t{1} << 20 : size,
                         options);
    } else {
      std::vector<char> block(size_t{1} << 20);
      while (const size_t got = read(block.data(), block.size())) {
        if (options.on_bytes) options.on_bytes(block.data(), got);
        text.append(block.data(), got);
        if (text.size() > static_cast<size_t>(kEstimateMaxBytes)) {
          throw ForceError(fmt::format(
              "{}: more than {} MiB of text with lines ended by CR alone; "
              "expected at most that (convert the line ends to LF first)",
              path,
              kEstimateMaxBytes >> 20));
        }
      }
    }
    ReadForceOptions text_options = options;
    text_options.on_bytes = nullptr;  // handed on as they were read
    return ReadForceText(text, path, text_options);
  }
  // Up to kEstimateMaxBytes, one pass, the columns sized from the file's
  // size (their room to spare, never written, ends as a few MiB of memory;
  // a 466 MB file's 12 M rows: 10 MiB more than counted, and the
  // analysis's peak 31 MiB more): on one thread, the checksum (if asked
  // for) taken from the bytes as they are parsed; on two, a large file's
  // rows after its first 54% parsed by the second thread, which first
  // counts the lines before them (54%: the first thread's rows take as
  // long as the second's count and rows). Larger files are counted first,
  // then split at the middle.
  const bool fits = !size_error && size > 0 &&
                    size <= static_cast<std::uintmax_t>(kEstimateMaxBytes);
  const bool split = options.threads >= 2 && !size_error &&
                     size >= static_cast<std::uintmax_t>(kSplitMinBytes);
  if (fits && (!split || !options.on_bytes)) {
    FileLines source(
        file.get(), path, options.max_line_bytes, options.on_bytes);
    if (!split) return Read(source, path, 0, options, nullptr, size);
    const SplitPoint at{
        path,
        static_cast<long>(static_cast<double>(size) * internal::kSplitShare),
        -1,
        0,
        &source};
    return Read(source, path, 0, options, &at, size);
  }
  const long middle = split ? static_cast<long>(size / 2) : -1;
  const LineCount count = CountLines(file.get(), options.on_bytes, middle);
  FileLines source(file.get(), path, options.max_line_bytes);
  if (count.split_offset < 0) return Read(source, path, count.lines, options);
  const SplitPoint at{
      path, middle, count.split_offset, count.lines_before_split, &source};
  return Read(source, path, count.lines, options, &at);
}

ForceRecord ReadForceText(const std::string& text,
                          const std::string& name,
                          const ReadForceOptions& options) {
  RefuseWorkbook(text, name);
  if (const char* encoding = Utf16Encoding(text)) {
    size_t at = 0;
    ReadForceOptions quiet = options;
    quiet.on_bytes = nullptr;  // ReadForceText hands on no bytes
    return ReadForceText(Utf16ToUtf8(
                             [&](char* into, size_t room) {
                               const size_t n =
                                   std::min(room, text.size() - at);
                               std::memcpy(into, text.data() + at, n);
                               at += n;
                               return n;
                             },
                             encoding,
                             name,
                             text.size(),
                             quiet),
                         name,
                         options);
  }
  if (EndsLinesWithCrAlone(text)) {
    std::string lf = text;
    std::replace(lf.begin(), lf.end(), '\r', '\n');
    return ReadForceText(lf, name, options);
  }
  MemoryLines source(text, name, options.max_line_bytes);
  const size_t lines =
      static_cast<size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
  return Read(source, name, lines, options);
}

}  // namespace wearscar::force
