#include "fields.h"

#include <fast_float/fast_float.h>

#include <cctype>
#include <cstdint>
#include <cstring>
#include <limits>

#include "wearscar/support/numbers.h"

namespace wearscar::force::internal {
namespace {

using support::kNaN;

bool IsBlank(char c) { return c == ' ' || c == '\t'; }

constexpr bool IsLittleEndian() {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
  return false;
#else
  return true;
#endif
}

// The digits at p (of the 8 bytes there, up to the first that is not a
// digit): appended to *mantissa (mantissa 10^n + their value, exact in 64
// bits while the whole has at most 19 digits); returns n. The bytes are
// read as one little-endian word, their digits combined in three
// multiplications (SWAR, as fast_float parses eight digits).
int EightDigits(const char* p, std::uint64_t* mantissa) {
  static constexpr std::uint64_t kPow10[] = {
      1, 10, 100, 1000, 10000, 100000, 1000000, 10000000, 100000000};
  std::uint64_t w;
  std::memcpy(&w, p, 8);
  if constexpr (!IsLittleEndian()) w = __builtin_bswap64(w);
  // A byte above '9' sets its top bit in the sum, one below '0' in the
  // difference; carries and borrows run only towards later bytes, past
  // the first non-digit, which both flag correctly.
  const std::uint64_t flagged =
      ((w + 0x4646464646464646ULL) | (w - 0x3030303030303030ULL)) &
      0x8080808080808080ULL;
  const int n = flagged == 0 ? 8 : __builtin_ctzll(flagged) / 8;
  if (n == 0) return 0;
  // The n digits' values in the word's last n bytes, zeros before them.
  std::uint64_t v = (w - 0x3030303030303030ULL) << (8 * (8 - n));
  v = (v * 10) + (v >> 8);
  v = (((v & 0x000000FF000000FFULL) * (100 + (1000000ULL << 32))) +
       (((v >> 16) & 0x000000FF000000FFULL) * (1 + (10000ULL << 32)))) >>
      32;
  *mantissa = *mantissa * kPow10[n] + v;
  return n;
}

// Plain fixed-point decimals ("-12.3456"), the bulk of every tribometer
// export, parsed in the one pass that finds the field's end: a field of at
// most 15 digits, an optional '-' (after an optional '+') and one decimal
// mark, between optional blanks, ending at the delimiter or the end of the
// row. With at most 15 digits the mantissa is exact, and so is 10^k, so a
// single division rounds correctly (Clinger's fast path) and gives the
// double fast_float gives. Returns the delimiter's place (or the end), the
// value in *out; null for anything else (an empty field, an exponent, a
// long mantissa, nan, inf, text), which FastRow then takes the general way.
const char* PlainField(
    const char* p, const char* end, char delim, char decimal, double* out) {
  const char* a = p;
  while (a < end && IsBlank(*a)) ++a;
  if (a < end && *a == '+') ++a;
  const bool negative = a < end && *a == '-';
  if (negative) ++a;
  // The integer digits, then (after the decimal mark) the fraction's: no
  // test of the mark per digit. The count is checked after the digits (a
  // longer mantissa wraps, unsigned, and is refused there).
  std::uint64_t mantissa = 0;
  const char* const first = a;
  for (unsigned d; a < end && (d = static_cast<unsigned char>(*a) - '0') < 10;
       ++a)
    mantissa = mantissa * 10 + d;
  int digits = static_cast<int>(a - first), fraction = 0;
  if (a < end && *a == decimal) {
    const char* const mark = ++a;
    // Up to eight of the fraction's digits at once where eight bytes of
    // the row follow (every field but a row's last).
    int n = 8;
    if (end - a >= 8) a += (n = EightDigits(a, &mantissa));
    for (unsigned d;
         n == 8 && a < end && (d = static_cast<unsigned char>(*a) - '0') < 10;
         ++a)
      mantissa = mantissa * 10 + d;
    fraction = static_cast<int>(a - mark);
    digits += fraction;
  }
  if (digits == 0 || digits > 15) return nullptr;
  while (a < end && IsBlank(*a)) ++a;
  if (a < end && *a != delim) return nullptr;
  const double v =
      static_cast<double>(mantissa) / support::kExactPowersOf10[fraction];
  *out = negative ? -v : v;
  return a;
}

// The end of the field starting at p: its delimiter, or the row's end.
const char* FieldEnd(const char* p, const char* end, char delim) {
  const char* q = p < end ? static_cast<const char*>(std::memchr(
                                p, delim, static_cast<std::size_t>(end - p)))
                          : nullptr;
  return q == nullptr ? end : q;
}

// A field between p and q by fast_float, blanks trimmed; an empty field is
// a gap (NaN). False for anything but a number.
bool GeneralField(const char* a,
                  const char* b,
                  const fast_float::parse_options& options,
                  double* v) {
  while (a < b && IsBlank(*a)) ++a;
  while (b > a && IsBlank(b[-1])) --b;
  if (a == b) {
    *v = kNaN;
    return true;
  }
  if (*a == '+') ++a;
  const auto r = fast_float::from_chars_advanced(a, b, *v, options);
  return r.ec == std::errc() && r.ptr == b;
}

}  // namespace

std::string_view TrimView(std::string_view s) {
  while (!s.empty() && IsBlank(s.front())) s.remove_prefix(1);
  while (!s.empty() && IsBlank(s.back())) s.remove_suffix(1);
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') {
    s = s.substr(1, s.size() - 2);
  }
  return s;
}

void Split(std::string_view line,
           char delim,
           std::vector<std::string_view>* cells) {
  cells->clear();
  std::size_t start = 0;
  for (;;) {
    std::size_t scan = start;
    while (scan < line.size() && IsBlank(line[scan]) && line[scan] != delim)
      ++scan;
    if (scan < line.size() && line[scan] == '"') {
      // Quoted: up to the closing quote (a doubled quote is an escape).
      std::size_t q = scan + 1;
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
    const std::size_t end = line.find(delim, scan);
    if (end == std::string_view::npos) {
      cells->push_back(TrimView(line.substr(start)));
      break;
    }
    cells->push_back(TrimView(line.substr(start, end - start)));
    start = end + 1;
  }
}

std::size_t CountWithoutTrailing(const std::vector<std::string_view>& cells) {
  return cells.size() > 1 && cells.back().empty() ? cells.size() - 1
                                                  : cells.size();
}

bool IsMissingMarker(std::string_view cell) {
  if (cell.size() < 2 || cell.size() > 9) return false;
  if (cell[0] == '-' || cell[0] == '+') cell.remove_prefix(1);
  char buffer[9];
  for (std::size_t i = 0; i < cell.size(); ++i) {
    buffer[i] =
        static_cast<char>(std::tolower(static_cast<unsigned char>(cell[i])));
  }
  const std::string_view lower(buffer, cell.size());
  return lower == "#n/a" || lower == "#nv" || lower == "#na" ||
         lower == "n/a" || lower == "na" || lower == "null" ||
         lower == "nan(ind)" || lower == "1.#qnan" || lower == "1.#ind";
}

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

bool FastRow(std::string_view row,
             char delim,
             char decimal,
             const std::vector<int>& slot_of_field,
             const Clock& clock,
             double* out) {
  const char* p = row.data();
  const char* const end = p + row.size();
  const std::size_t columns = slot_of_field.size();
  const fast_float::parse_options options{fast_float::chars_format::general,
                                          decimal};
  // (A decimal mark that is also the delimiter cannot end a field.)
  const bool plain = decimal != delim;
  std::size_t field = 0;
  for (;; ++field) {
    const int slot = field < columns ? slot_of_field[field] : -1;
    const char* q = nullptr;
    if (static_cast<int>(field) == clock.field) {
      q = FieldEnd(p, end, delim);
      if (!ClockSeconds(clock,
                        std::string_view(p, static_cast<std::size_t>(q - p)),
                        &out[slot]))
        return false;
    } else if (slot >= 0) {
      q = plain ? PlainField(p, end, delim, decimal, &out[slot]) : nullptr;
      if (q == nullptr) {
        q = FieldEnd(p, end, delim);
        if (!GeneralField(p, q, options, &out[slot])) return false;
      }
    } else {
      q = FieldEnd(p, end, delim);
    }
    if (q == end) break;
    p = q + 1;
  }
  ++field;
  return field == columns ||
         (field == columns + 1 && !row.empty() && row.back() == delim);
}

}  // namespace wearscar::force::internal
