#pragma once

#include <filesystem>
#include <string>

namespace wearscar::scan::internal {

// Whole file into memory; throws ScanError naming the file. Files larger
// than `max_bytes` are refused before reading.
// "a FIFO", "a directory", ... for messages.
const char* DescribeFileType(std::filesystem::file_type type);

std::string ReadFileBytes(const std::string& path,
                          size_t max_bytes = size_t{1} << 32);

// Writes bytes to a temporary name beside `path`, then renames.
void WriteFileAtomically(const std::string& path, const std::string& bytes);

}  // namespace wearscar::scan::internal
