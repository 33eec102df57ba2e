#pragma once
// A large file's rows on two threads: a second thread parses the ordinary
// rows after a split point while the first reads those before, and they
// are taken only where one pass would have read them the same.

#include <cstdint>
#include <string>

#include "line_source.h"
#include "row_reader.h"
#include "wearscar/force/read_force.h"

namespace wearscar::force::internal {

// Files smaller than this are parsed on one thread.
inline constexpr std::uintmax_t kSplitMinBytes = std::uintmax_t{2} << 20;

// Reads the data lines of `lines` (the file `path` of `file_bytes` bytes,
// `line_no` lines read so far) into `rows`, the rows after
// options.split_share of the bytes on a second thread; the lines neither
// took are left to the caller. Returns the lines read.
long ReadRowsOnTwoThreads(RowReader& rows,
                          FileLines& lines,
                          long line_no,
                          int first_data_line,
                          const std::string& path,
                          std::uintmax_t file_bytes,
                          const ReadForceOptions& options);

}  // namespace wearscar::force::internal
