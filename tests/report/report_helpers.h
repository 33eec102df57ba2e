// Folders and files for the wearscar::report suites.
#pragma once

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

namespace wearscar::report::test_support {

// A new folder under the temporary directory, named after `what`.
inline std::filesystem::path FreshFolder(const std::string& what) {
  const std::filesystem::path p =
      std::filesystem::temp_directory_path() /
      fmt::format("wearscar-report-{}-{:08x}", what, std::random_device{}());
  std::filesystem::create_directories(p);
  return p;
}

inline std::string Slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace wearscar::report::test_support
