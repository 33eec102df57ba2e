#pragma once

#include <cstddef>
#include <functional>
#include <string>

#include "wearscar/force/force_record.h"

namespace wearscar::force {

// How to read a delimited force export. Every field may stay at its default:
// the reader detects the delimiter, the decimal mark, the header and unit
// rows and the columns.
struct ReadForceOptions {
  // Column overrides: a header name (case-insensitive, exact) or a 1-based
  // column number written as "#3". Empty = find by pattern. A time column
  // of "none": the file's time column (if any) is not read, the clock is
  // rebuilt from the metadata's rate or sampling_rate_hz.
  std::string time_column;
  std::string x_column;
  std::string tangential_column;
  std::string normal_column;
  // The depth channel (the ball's vertical position): found by name when
  // empty; "none" reads none.
  std::string depth_column;
  // Units of x, of both forces and of time: empty = the file's; where the
  // file states none, inferred from plausibility (tribometer strokes of
  // 0.05-50 mm, loads of 0.01-5000 N, sampling at 1 Hz-1 MHz) with a
  // warning naming the assumption, refused when no unit is plausible. A
  // unit given here overrides the file's (a warning says when they differ).
  std::string x_unit;
  std::string force_unit;
  std::string time_unit;
  // Unit of the depth channel (um, mm, nm); default: the file's, else um
  // with a warning.
  std::string depth_unit;
  // Rebuild time from this rate when there is no time column and the
  // metadata gives none; 0 = required from the file.
  double sampling_rate_hz = 0.0;
  // Drop isolated bad rows with a counted warning instead of failing.
  bool lenient = false;
  // Read Q and P as they are even when they cannot be a friction force and
  // a load (|Q| above |P| on most samples, a load changing sign); refused
  // otherwise, naming the fix.
  bool channels_as_given = false;
  // Lenient mode still fails when more than this fraction of rows is bad.
  double max_dropped_fraction = 0.01;
  // Longest run of NaN samples accepted in any channel.
  int max_nan_run = 50;
  // Longest line, bytes: a file without line breaks is not a text export
  // (and is refused before it fills the memory).
  std::size_t max_line_bytes = std::size_t{1} << 22;
  // Lines read before the data to find the delimiter, header, units and
  // metadata; the last delimiter_vote_lines non-empty ones of them vote for
  // the delimiter.
  int head_lines = 400;
  int delimiter_vote_lines = 20;
  // ReadForceFile hands every byte of the file, in order, to this as its
  // first pass reads them (a checksum of the file then costs no read of
  // its own); ReadForceText does not call it.
  std::function<void(const char* bytes, std::size_t size)> on_bytes;
  // With 2, ReadForceFile parses a file of 2-256 MiB on two threads (not
  // when on_bytes is set): a second thread parses the ordinary rows after
  // `split_share` of its bytes while the first reads those before, and
  // they are taken only where one pass would have read them the same
  // (the record, warnings and errors are one thread's).
  int threads = 1;
  double split_share = 0.54;
  bool IsValid(std::string* why) const;
};

// Reads a delimited (CSV, semicolon, tab) tribometer export: generic files
// and the layouts of the registry (wearscar/force/layouts.h;
// docs/formats.md). Converts to s, mm, N and makes P positive in
// compression. Throws ForceError.
ForceRecord ReadForceFile(const std::string& path,
                          const ReadForceOptions& options = {});

// Same, from text already in memory; `name` is used in messages.
ForceRecord ReadForceText(const std::string& text,
                          const std::string& name,
                          const ReadForceOptions& options = {});

// Writes time_s, x_mm, Q_N, P_N as CSV (temporary name, then rename).
void WriteForceCsv(const ForceRecord& record, const std::string& path);

// Writes an Rtec MFT-like recipe CSV: a recipe line, `RecipeStep,Timestamp,
// DAQ.Fx (N),DAQ.Fz (N),DAQ.COF (),Piezo X (mm),` with trailing commas, Fz
// negative in compression, the Timestamp restarting with every recipe step
// (steps of `step_s` seconds), and a footer. ReadForceFile reads it back.
void WriteRtecCsv(const ForceRecord& record,
                  const std::string& path,
                  double step_s = 10.0);

}  // namespace wearscar::force
