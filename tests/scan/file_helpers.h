// Reading and writing whole files in the scan suite.
#pragma once

#include <fstream>
#include <iterator>
#include <string>

namespace wearscar::scan::test_files {

inline std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline void Spit(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

}  // namespace wearscar::scan::test_files
