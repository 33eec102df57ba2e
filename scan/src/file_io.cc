#include "file_io.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "wearscar/scan/height_map.h"
#include "wearscar/support/atomic_file.h"

namespace wearscar::scan::internal {

const char* DescribeFileType(std::filesystem::file_type type) {
  switch (type) {
    case std::filesystem::file_type::directory:
      return "a directory";
    case std::filesystem::file_type::fifo:
      return "a FIFO";
    case std::filesystem::file_type::character:
      return "a character device";
    case std::filesystem::file_type::block:
      return "a block device";
    case std::filesystem::file_type::socket:
      return "a socket";
    case std::filesystem::file_type::not_found:
      return "not found";
    default:
      return "not a file";
  }
}

std::string ReadFileBytes(const std::string& path, size_t max_bytes) {
  std::error_code ec;
  // A FIFO would block, a device never end: regular files only.
  const auto status = std::filesystem::status(path, ec);
  if (ec)
    throw ScanError(fmt::format("{}: cannot open: {}", path, ec.message()));
  if (!std::filesystem::is_regular_file(status)) {
    throw ScanError(
        fmt::format("{}: not a regular file ({}); expected a height map file",
                    path,
                    DescribeFileType(status.type())));
  }
  const auto size = std::filesystem::file_size(path, ec);
  if (ec)
    throw ScanError(fmt::format("{}: cannot open: {}", path, ec.message()));
  if (size > max_bytes) {
    throw ScanError(
        fmt::format("{}: file of {} bytes exceeds the limit of {} bytes",
                    path,
                    size,
                    max_bytes));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw ScanError(
        fmt::format("{}: cannot open: {}", path, std::strerror(errno)));
  std::string bytes(size, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (static_cast<size_t>(in.gcount()) != size) {
    throw ScanError(
        fmt::format("{}: read {} of {} bytes", path, in.gcount(), size));
  }
  return bytes;
}

void WriteFileAtomically(const std::string& path, const std::string& bytes) {
  support::WriteFileAtomically<ScanError>(path, bytes);
}

}  // namespace wearscar::scan::internal
