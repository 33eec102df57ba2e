#include "line_source.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "wearscar/force/force_record.h"

namespace wearscar::force::internal {
namespace {

// A read's block, 256 KiB: a reader's buffers are new pages the kernel
// zeroes (docs/performance.md), and a larger block reads no faster.
constexpr std::size_t kBlock = std::size_t{1} << 18;

ForceError TooLong(const std::string& name, long line, std::size_t max) {
  return ForceError(fmt::format(
      "{}: line {}: more than {} bytes without a line break; expected a "
      "delimited text export",
      name,
      line,
      max));
}

void DropCarriageReturn(std::string_view* line) {
  if (!line->empty() && line->back() == '\r') line->remove_suffix(1);
}

}  // namespace

bool MemoryLines::Next(std::string_view* line) {
  if (pos_ >= text_.size()) return false;
  std::size_t end = text_.find('\n', pos_);
  if (end == std::string_view::npos) end = text_.size();
  ++lines_;
  if (end - pos_ > max_line_) throw TooLong(name_, lines_, max_line_);
  *line = text_.substr(pos_, end - pos_);
  DropCarriageReturn(line);
  pos_ = end + 1;
  return true;
}

FileLines::FileLines(std::FILE* file,
                     std::string name,
                     std::size_t max_line,
                     std::function<void(const char*, std::size_t)> on_bytes)
    : file_(file),
      name_(std::move(name)),
      max_line_(max_line),
      on_bytes_(std::move(on_bytes)),
      buffer_(std::min(kBlock, std::max<std::size_t>(max_line, 1024))) {}

bool FileLines::Next(std::string_view* line) {
  for (;;) {
    const char* begin = buffer_.data() + pos_;
    const char* nl =
        static_cast<const char*>(std::memchr(begin, '\n', filled_ - pos_));
    if (nl != nullptr) {
      *line = std::string_view(begin, static_cast<std::size_t>(nl - begin));
      pos_ = static_cast<std::size_t>(nl - buffer_.data()) + 1;
      ++lines_;
      DropCarriageReturn(line);
      return true;
    }
    if (eof_) {
      if (pos_ >= filled_) return false;
      *line = std::string_view(begin, filled_ - pos_);
      pos_ = filled_;
      ++lines_;
      DropCarriageReturn(line);
      return true;
    }
    Refill();
  }
}

// Moves the partial line to the front and reads more; grows only for a
// long line, up to the bound (a text export's lines are short; one without
// breaks is not a text export).
void FileLines::Refill() {
  base_ += pos_;
  std::memmove(buffer_.data(), buffer_.data() + pos_, filled_ - pos_);
  filled_ -= pos_;
  pos_ = 0;
  if (filled_ == buffer_.size()) {
    if (buffer_.size() >= max_line_)
      throw TooLong(name_, lines_ + 1, max_line_);
    buffer_.resize(buffer_.size() * 2);
  }
  const std::size_t got =
      std::fread(buffer_.data() + filled_, 1, buffer_.size() - filled_, file_);
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

void FileLines::SeekTo(std::uintmax_t offset, long lines_before) {
  if (std::fseek(file_, static_cast<long>(offset), SEEK_SET) != 0) {
    throw ForceError(
        fmt::format("{}: seek failed: {}", name_, std::strerror(errno)));
  }
  base_ = offset;
  pos_ = filled_ = 0;
  lines_ = lines_before;
  eof_ = false;
}

std::size_t CountLineBreaks(const char* begin, const char* end) {
  std::size_t lines = 0;
  while (begin < end) {
    const char* stop = begin + std::min<std::ptrdiff_t>(255, end - begin);
    unsigned char run = 0;
    for (; begin < stop; ++begin) run += *begin == '\n';
    lines += run;
  }
  return lines;
}

LineStart FirstLineAfter(std::FILE* file, std::uintmax_t middle) {
  std::vector<char> block(kBlock);
  LineStart start;
  std::uintmax_t at = 0;
  long lines = 0;
  std::size_t got;
  while ((got = std::fread(block.data(), 1, block.size(), file)) > 0) {
    const char* begin = block.data();
    const char* end = begin + got;
    // Lines wholly before the middle are counted a block at a time.
    const char* from = begin;
    if (at + got <= middle) {
      lines += static_cast<long>(CountLineBreaks(begin, end));
      at += got;
      continue;
    }
    if (at < middle) {
      from = begin + (middle - at);
      lines += static_cast<long>(CountLineBreaks(begin, from));
    }
    if (const char* nl =
            static_cast<const char*>(std::memchr(from, '\n', end - from))) {
      start.offset = static_cast<long long>(at + (nl - begin) + 1);
      start.lines_before = lines + 1;
      return start;
    }
    at += got;
  }
  return start;
}

std::size_t CountLines(
    std::FILE* file,
    const std::function<void(const char*, std::size_t)>& on_bytes) {
  std::vector<char> block(kBlock);
  std::size_t lines = 1, got;
  while ((got = std::fread(block.data(), 1, block.size(), file)) > 0) {
    if (on_bytes) on_bytes(block.data(), got);
    lines += CountLineBreaks(block.data(), block.data() + got);
  }
  std::rewind(file);
  return lines;
}

}  // namespace wearscar::force::internal
