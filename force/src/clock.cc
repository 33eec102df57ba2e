#include "clock.h"

#include <limits>

#include "fields.h"

namespace wearscar::force::internal {
namespace {

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

// Reads digits and marks from a cell, front to back.
struct Cursor {
  const char* p;
  const char* end;

  bool Number(int min_digits, int max_digits, long* v) {
    int n = 0;
    *v = 0;
    while (p < end && n < max_digits && *p >= '0' && *p <= '9') {
      *v = *v * 10 + (*p++ - '0');
      ++n;
    }
    return n >= min_digits;
  }
  bool Take(char c) {
    if (p < end && *p == c) {
      ++p;
      return true;
    }
    return false;
  }
  // A fraction of a second after '.' or ',' (to the nanosecond; digits
  // beyond are skipped), 0 when there is none; false for a mark without
  // digits.
  bool Fraction(double* fraction) {
    *fraction = 0;
    if (!(p < end && (*p == '.' || *p == ','))) return true;
    ++p;
    long digits = 0, scale = 1;
    int n = 0;
    while (p < end && *p >= '0' && *p <= '9' && n < 9) {
      digits = digits * 10 + (*p++ - '0');
      scale *= 10;
      ++n;
    }
    if (n == 0) return false;
    while (p < end && *p >= '0' && *p <= '9') ++p;
    *fraction = static_cast<double>(digits) / static_cast<double>(scale);
    return true;
  }
};

// "2024-05-01 " / "2024-05-01T" or "01.05.2024 ": the date's days, or
// false with the cursor where it was.
bool ParseDate(Cursor* c, long* days) {
  const char* start = c->p;
  long a = 0, b = 0, d = 0;
  if (c->Number(4, 4, &a) && c->Take('-') && c->Number(2, 2, &b) &&
      c->Take('-') && c->Number(2, 2, &d) && (c->Take(' ') || c->Take('T'))) {
    if (b < 1 || b > 12 || d < 1 || d > 31) return false;
    *days =
        DaysFromCivil(a, static_cast<unsigned>(b), static_cast<unsigned>(d));
    return true;
  }
  c->p = start;
  if (c->Number(1, 2, &a) && c->Take('.') && c->Number(1, 2, &b) &&
      c->Take('.') && c->Number(4, 4, &d) && c->Take(' ')) {
    if (b < 1 || b > 12 || a < 1 || a > 31) return false;
    *days =
        DaysFromCivil(d, static_cast<unsigned>(b), static_cast<unsigned>(a));
    return true;
  }
  c->p = start;
  return false;
}

}  // namespace

bool ParseClock(std::string_view cell,
                long* days,
                double* seconds,
                bool* dated) {
  cell = TrimView(cell);
  Cursor c{cell.data(), cell.data() + cell.size()};
  *days = 0;
  *dated = false;
  const char* start = c.p;
  if (ParseDate(&c, days)) {
    *dated = true;
  } else if (c.p != start) {
    return false;
  }
  // A date that fails its ranges leaves the cursor moved: refused above.
  while (c.p < c.end && *c.p == ' ') ++c.p;
  long h = 0, m = 0, sec = 0;
  if (!(c.Number(1, 2, &h) && c.Take(':') && c.Number(2, 2, &m))) return false;
  double fraction = 0;
  if (c.Take(':') && !(c.Number(2, 2, &sec) && c.Fraction(&fraction)))
    return false;
  c.Take('Z');
  if (c.p != c.end || h > 23 || m > 59 || sec > 60) return false;
  *seconds = static_cast<double>(h * 3600 + m * 60 + sec) + fraction;
  return true;
}

bool ClockSeconds(const Clock& clock, std::string_view cell, double* value) {
  long days;
  double seconds;
  bool dated;
  if (cell.empty() || IsMissingMarker(cell)) {
    *value = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  if (!ParseClock(cell, &days, &seconds, &dated) || dated != clock.dated)
    return false;
  *value = static_cast<double>(days - clock.origin_days) * 86400.0 +
           (seconds - clock.origin_seconds);
  return true;
}

}  // namespace wearscar::force::internal
