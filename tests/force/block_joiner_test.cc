// A test written as a file per block, joined as the blocks grow.

#include "wearscar/force/block_joiner.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace wearscar::force {
namespace {

namespace fs = std::filesystem;

std::string Read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void Append(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::app) << text;
}

TEST(NaturalLess, ComparesRunsOfDigitsAsNumbers) {
  EXPECT_TRUE(NaturalLess("run_2.csv", "run_10.csv"));
  EXPECT_FALSE(NaturalLess("run_10.csv", "run_2.csv"));
  EXPECT_TRUE(NaturalLess("run_02.csv", "run_3.csv"));
  EXPECT_TRUE(NaturalLess("a", "b"));
  EXPECT_TRUE(NaturalLess("run", "run_1"));
  EXPECT_FALSE(NaturalLess("run_7.csv", "run_7.csv"));
}

TEST(BlockJoiner, JoinsCompleteLinesAndFinishesABlockOnceALaterOneExists) {
  const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::path(::testing::TempDir()) /
                       ("wearscar-" + std::string(test->name()));
  fs::remove_all(dir);
  fs::create_directories(dir / "blocks");
  const std::string blocks = (dir / "blocks").string();
  const std::string joined = (dir / "joined.csv").string();
  BlockJoiner j(blocks, "run_*.csv", joined);
  EXPECT_EQ(j.Update(), "");  // no block yet
  Append(blocks + "/run_2.csv", "t,x\n0,1\n0.1,");
  Append(blocks + "/other.csv", "not a block\n");
  EXPECT_EQ(j.Update(), "block run_2.csv started");
  EXPECT_EQ(Read(joined), "t,x\n0,1\n");  // not the row being written
  Append(blocks + "/run_2.csv", "2\n0.2,3");
  // run_10 comes after run_2: run_2 is finished, its last row taken with a
  // line break.
  Append(blocks + "/run_10.csv", "t,x\n0.3,4\n");
  EXPECT_EQ(j.Update(), "block run_2.csv finished; block run_10.csv started");
  EXPECT_EQ(Read(joined), "t,x\n0,1\n0.1,2\n0.2,3\nt,x\n0.3,4\n");
  EXPECT_EQ(j.blocks().size(), 2u);
  EXPECT_EQ(j.Update(), "");  // nothing new: nothing taken twice
  EXPECT_EQ(Read(joined), "t,x\n0,1\n0.1,2\n0.2,3\nt,x\n0.3,4\n");
  fs::remove_all(dir);
}

TEST(BlockJoiner, RefusesAFileForItsFolderAndAnEmptyPattern) {
  const std::string file = ::testing::TempDir() + "/wearscar-not-a-folder.csv";
  std::ofstream(file) << "t,x\n";
  try {
    BlockJoiner j(file, "run_*.csv", file + ".joined");
    FAIL() << "a file taken for the blocks' folder";
  } catch (const ForceError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "is not a folder (the blocks' folder is expected)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(BlockJoiner(::testing::TempDir(), "", file + ".joined"),
               ForceError);
  fs::remove(file);
}

}  // namespace
}  // namespace wearscar::force
