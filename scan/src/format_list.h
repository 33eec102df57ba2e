#pragma once

// The registry of height-map formats, one line each: X(Function) names the
// function `ScanFormat Function()` that the format's source file defines
// in wearscar::scan::internal. The order breaks ties between equal scores
// (the text layouts come last: they read what nothing else claims).
#define WEARSCAR_SCAN_FORMATS(X) \
  X(KeyenceZagFormat)            \
  X(KeyenceZonFormat)            \
  X(KeyenceVk4Format)            \
  X(KeyenceVk67Format)           \
  X(X3pFormat)                   \
  X(GsfFormat)                   \
  X(SensofarPluFormat)           \
  X(AliconaAl3dFormat)           \
  X(WykoOpdFormat)               \
  X(DigitalSurfFormat)           \
  X(ZygoMetroProFormat)          \
  X(KeyenceCsvFormat)            \
  X(AsciiMatrixFormat)
