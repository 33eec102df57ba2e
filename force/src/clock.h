#pragma once
// A time column written as a date and time of day ("2024-05-01
// 12:00:00.125", "01.05.2024 12:00:00,125") or a time of day alone: read
// as seconds since the first data row's reading.

#include <string_view>

namespace wearscar::force::internal {

struct Clock {
  int field = -1;      // the column, -1 = the time column holds numbers
  bool dated = false;  // a date with the time of day (else it may wrap)
  long origin_days = 0;
  double origin_seconds = 0;
};

// A date and time of day as instruments and LabVIEW rigs log them:
// "2024-05-01 12:00:00.125" (or with 'T'), "01.05.2024 12:00:00,125", or a
// time of day alone, "12:00:00.125" (seconds and their fraction optional
// after the minutes; a trailing 'Z' allowed). Days since 1970-01-01 (0
// without a date), seconds of the day, and whether a date was given. False
// for anything else (a '/' date, whose day and month order is unknowable).
bool ParseClock(std::string_view cell,
                long* days,
                double* seconds,
                bool* dated);

// The clock's value of a cell: seconds since the origin (NaN for an empty
// cell or a missing-value marker); false if the cell is not a clock
// reading of the clock's kind.
bool ClockSeconds(const Clock& clock, std::string_view cell, double* value);

}  // namespace wearscar::force::internal
