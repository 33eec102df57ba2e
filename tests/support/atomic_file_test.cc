#include "wearscar/support/atomic_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace wearscar::support {
namespace {

namespace fs = std::filesystem;

struct TestError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

fs::path FreshFolder(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("wearscar-support-" + name);
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

std::string Slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(AtomicFile, NothingAppearsUntilCommit) {
  const fs::path dir = FreshFolder("commit");
  const fs::path target = dir / "table.csv";
  {
    AtomicFile<TestError> f(target.string());
    f.Write("x_mm,");
    f.Write("Q_N\n");
    EXPECT_FALSE(fs::exists(target));
    f.Commit();
  }
  EXPECT_EQ(Slurp(target), "x_mm,Q_N\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), {}), 1);
}

TEST(AtomicFile, DestroyedUncommittedLeavesNothingAndTheOldFile) {
  const fs::path dir = FreshFolder("abandon");
  const fs::path target = dir / "result.json";
  WriteFileAtomically<TestError>(target.string(), "old");
  {
    AtomicFile<TestError> f(target.string());
    f.Write("half of the new");
  }
  EXPECT_EQ(Slurp(target), "old");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), {}), 1);
}

TEST(AtomicFile, FailureThrowsTheCallersErrorWithPathAndReason) {
  const fs::path target = FreshFolder("missing") / "no" / "such" / "x.csv";
  try {
    WriteFileAtomically<TestError>(target.string(), "x");
    FAIL() << "no error";
  } catch (const TestError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(target.string() + ": cannot write: "), std::string::npos)
        << m;
    EXPECT_NE(m.find("No such file or directory"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace wearscar::support
