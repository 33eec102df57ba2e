#pragma once
// A force export that the tribometer's software is still writing, read as
// it grows: the rows appended since the last look, never a row still being
// written, and a file replaced or truncated (a new test) said and read
// from its start.

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "wearscar/force/force_record.h"
#include "wearscar/force/read_force.h"

namespace wearscar::force {
namespace internal {
struct ReadPlan;  // what the header decided (appended_rows.h)
}

struct FollowOptions {
  ReadForceOptions read;
  // The header, units and first rows are read (the layout detected, the
  // units decided) once the file holds this many complete lines, or once
  // it has stopped growing with at least head_lines + 2 of them
  // (Poll(true)).
  int first_lines = 2000;
  // At most this much of the file is taken in one Poll (the rest at the
  // next): memory stays bounded however far behind the reader is.
  std::size_t max_bytes_per_poll = std::size_t{16} << 20;
};

// What one look at the file found.
struct FollowedRows {
  // The complete rows appended since the last look, in s, mm and N, on the
  // clock of the rows before them (a restarted clock joined); empty when
  // none. metadata: the file's (layout, units, warnings), as read from its
  // first rows.
  ForceRecord rows;
  // The file was replaced or truncated: `rows` start a new test (from its
  // first row); what was read before is another test's.
  bool restarted = false;
  // One line for the user when something happened (a restart, the file
  // appearing); empty otherwise.
  std::string note;
};

class ForceFollower {
 public:
  ForceFollower(std::string path, FollowOptions options);
  ~ForceFollower();
  ForceFollower(const ForceFollower&) = delete;
  ForceFollower& operator=(const ForceFollower&) = delete;

  // Reads what was appended since the last call. `idle`: the caller has
  // seen the file stop growing, so a short file's first rows are read
  // without waiting for FollowOptions::first_lines. A last line without
  // its line break is never taken (a writer killed mid-row leaves it to
  // the reader of the whole file, which says so). Throws ForceError for a
  // file that cannot be read as a force export (naming the file and, for
  // appended rows, the line they start at).
  FollowedRows Poll(bool idle = false);

  // Whether the header has been read (metadata() is the file's).
  bool started() const { return started_; }
  const ForceMetadata& metadata() const { return first_; }
  // Bytes of the file taken so far (complete lines), and its lines.
  std::uintmax_t offset() const { return offset_; }
  long lines() const { return lines_; }
  const std::string& path() const { return path_; }

 private:
  struct FileCloser {
    void operator()(std::FILE* f) const {
      if (f != nullptr) std::fclose(f);
    }
  };
  void Reset();
  bool Reopen(FollowedRows* out);
  std::string TakeCompleteLines();
  void ReadFirstRows(const std::string& text, FollowedRows* out);
  void ReadMoreRows(const std::string& text,
                    long text_lines,
                    FollowedRows* out);

  std::string path_;
  FollowOptions options_;
  std::unique_ptr<std::FILE, FileCloser> file_;
  std::uintmax_t inode_ = 0, device_ = 0;
  std::uintmax_t offset_ = 0;  // bytes taken into lines
  std::uintmax_t read_ = 0;    // bytes read (offset_ + pending_)
  long lines_ = 0;
  std::string pending_;  // read, not yet a complete line
  // What each read takes from the file (allocated once: at most 1 MiB,
  // never zeroed).
  std::unique_ptr<char[]> block_;
  std::size_t block_size_ = 0;
  std::string head_;  // complete lines before the first rows are read
  bool started_ = false;
  bool announced_missing_ = false;
  ForceMetadata first_;
  std::string header_;  // the lines before the first data row
  // The last data lines read (the next text's first) and how many.
  std::string last_rows_;
  int last_row_count_ = 0;  // the data rows among them (OverlapRows)
  int OverlapRows() const;
  double last_time_s_ = 0.0;
  // The layout, columns, clock and units, found on the first rows
  // appended and kept for the next.
  std::shared_ptr<internal::ReadPlan> plan_;
};

}  // namespace wearscar::force
