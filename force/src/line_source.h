#pragma once
// Line sources: the reader streams a file in blocks so that its text is
// never held whole beside the numbers (memory stays near the numeric
// data's).

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace wearscar::force::internal {

class LineSource {
 public:
  virtual ~LineSource() = default;
  // Next line without its terminator ("\n" or "\r\n"); false at the end.
  // Throws ForceError for a line longer than the source's bound.
  virtual bool Next(std::string_view* line) = 0;
};

// Lines of text in memory.
class MemoryLines : public LineSource {
 public:
  MemoryLines(std::string_view text, std::string name, std::size_t max_line)
      : text_(text), name_(std::move(name)), max_line_(max_line) {}
  bool Next(std::string_view* line) override;

 private:
  std::string_view text_;
  std::string name_;
  std::size_t max_line_;
  std::size_t pos_ = 0;
  long lines_ = 0;
};

// Lines of an open file, read in blocks of 1 MiB.
class FileLines : public LineSource {
 public:
  // `on_bytes`, when given, is handed every byte read, in order (the whole
  // file: the reader never seeks).
  FileLines(std::FILE* file,
            std::string name,
            std::size_t max_line,
            std::function<void(const char*, std::size_t)> on_bytes = {});
  bool Next(std::string_view* line) override;
  // The file offset of the next line's first byte.
  std::uintmax_t Offset() const { return base_ + pos_; }
  // Goes on from `offset`, the first byte of line `lines_before` + 1.
  void SeekTo(std::uintmax_t offset, long lines_before);

 private:
  void Refill();
  std::FILE* file_;
  std::string name_;
  std::size_t max_line_;
  std::function<void(const char*, std::size_t)> on_bytes_;
  std::vector<char> buffer_;
  std::uintmax_t base_ = 0;  // the file offset of buffer_[0]
  std::size_t pos_ = 0, filled_ = 0;
  long lines_ = 0;
  bool eof_ = false;
};

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

// The line breaks in [begin, end): a byte counter per 255 bytes, which the
// compiler turns into wide compares (std::count widens every byte to a
// 64-bit sum: four times slower on a 45 MB export).
std::size_t CountLineBreaks(const char* begin, const char* end);

// The lines of an open file (line breaks + 1), each byte handed to
// `on_bytes` when given; the file is rewound after.
std::size_t CountLines(
    std::FILE* file,
    const std::function<void(const char*, std::size_t)>& on_bytes);

// The first line that starts after byte `middle` of an open file: its
// offset and the lines before it (offset -1: none). Reads no further.
struct LineStart {
  long long offset = -1;
  long lines_before = 0;
};
LineStart FirstLineAfter(std::FILE* file, std::uintmax_t middle);

}  // namespace wearscar::force::internal
